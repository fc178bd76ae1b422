#include "marchcheck/march/render.hpp"

#include <sys/mman.h>

#include <cstdint>
#include <cstdlib>
#include <new>

namespace marchcheck::march {

namespace {
constexpr std::size_t kHugePage = std::size_t(2) << 20;

// Where a large block's allocation starts: kept in the word just before the aligned block.
void*& allocation_of(void* block) { return static_cast<void**>(block)[-1]; }
}  // namespace

void* allocate_pixels(std::size_t bytes) {
  if (bytes < kHugePage) return ::operator new(bytes);
  const std::size_t whole = (bytes + kHugePage - 1) & ~(kHugePage - 1);
  // Aligned here rather than by glibc's aligned allocation, whose split-off head and tail fragment the heap: the
  // next render's image then no longer fits what this one frees and lands on fresh pages (test_render.cpp).
  void* allocation = std::malloc(whole + kHugePage);
  if (allocation == nullptr) throw std::bad_alloc();
  const std::uintptr_t past_header = reinterpret_cast<std::uintptr_t>(allocation) + sizeof(void*);
  void* block = reinterpret_cast<void*>((past_header + kHugePage - 1) & ~(kHugePage - 1));
  allocation_of(block) = allocation;
  // Advice only: a kernel without transparent huge pages refuses it, and the pages stay 4 KiB.
  madvise(block, whole, MADV_HUGEPAGE);
  return block;
}

void free_pixels(void* block, std::size_t bytes) {
  if (bytes < kHugePage) ::operator delete(block);
  else std::free(allocation_of(block));
}

}  // namespace marchcheck::march
