#include "marchcheck/march/render.hpp"

#include <sys/mman.h>

#include <new>

namespace marchcheck::march {

namespace {
constexpr std::size_t kHugePage = std::size_t(2) << 20;
}

void* allocate_pixels(std::size_t bytes) {
  if (bytes < kHugePage) return ::operator new(bytes);
  const std::size_t whole = (bytes + kHugePage - 1) & ~(kHugePage - 1);
  void* block = ::operator new(whole, std::align_val_t(kHugePage));
  // Advice only: a kernel without transparent huge pages refuses it, and the pages stay 4 KiB.
  madvise(block, whole, MADV_HUGEPAGE);
  return block;
}

void free_pixels(void* block, std::size_t bytes) {
  if (bytes < kHugePage) ::operator delete(block);
  else ::operator delete(block, std::align_val_t(kHugePage));
}

}  // namespace marchcheck::march
