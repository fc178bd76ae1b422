#include "huge_pages.hpp"

#include "marchcheck/march/render.hpp"

#include <sys/mman.h>

#include <cstdint>
#include <new>

namespace marchcheck::march {

namespace {
constexpr std::size_t kHugePage = std::size_t(2) << 20;
}

void advise_huge_pages(void* data, std::size_t bytes) {
  const auto begin = reinterpret_cast<std::uintptr_t>(data);
  const std::uintptr_t first = (begin + kHugePage - 1) & ~(kHugePage - 1), last = (begin + bytes) & ~(kHugePage - 1);
  // Advice only: a kernel without transparent huge pages refuses it, and the pages stay 4 KiB.
  if (first < last) madvise(reinterpret_cast<void*>(first), last - first, MADV_HUGEPAGE);
}

void* allocate_pixels(std::size_t bytes) {
  if (bytes < kHugePage) return ::operator new(bytes);
  const std::size_t whole = (bytes + kHugePage - 1) & ~(kHugePage - 1);
  void* block = ::operator new(whole, std::align_val_t(kHugePage));
  advise_huge_pages(block, whole);
  return block;
}

void free_pixels(void* block, std::size_t bytes) {
  if (bytes < kHugePage) ::operator delete(block);
  else ::operator delete(block, std::align_val_t(kHugePage));
}

}  // namespace marchcheck::march
