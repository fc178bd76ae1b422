// The one probe of glibc's allocator policy that the tests of march::keep_freed_memory share.
#pragma once

#include <malloc.h>

#include <cstddef>
#include <cstdlib>

namespace marchcheck::testing {

// Whether glibc maps a block of `bytes` on its own (mallinfo2's hblks), as it does above its mmap threshold, rather
// than taking it from the heap. The block is freed before it returns.
inline bool mapped_on_its_own(std::size_t bytes) {
  const std::size_t before = mallinfo2().hblks;
  void* block = std::malloc(bytes);
  asm volatile("" : : "r"(block) : "memory");  // the block is used: the allocation stays
  const bool mapped = block == nullptr || mallinfo2().hblks != before;
  std::free(block);
  return mapped;
}

}  // namespace marchcheck::testing
