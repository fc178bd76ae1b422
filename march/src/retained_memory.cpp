#include "marchcheck/march/render.hpp"

#if defined(__GLIBC__)
#include <malloc.h>
#endif

namespace marchcheck::march {

void keep_freed_memory() {
#if defined(__GLIBC__)
  // Blocks below 32 MiB (a 1920x1080 colour image is 24 MiB) come from the heap, and the heap is not trimmed below
  // 1 GiB of free memory: a render's buffers then reuse what the last render freed, pages already faulted in.
  mallopt(M_MMAP_THRESHOLD, 32 << 20);
  mallopt(M_TRIM_THRESHOLD, 1 << 30);
#endif
}

}  // namespace marchcheck::march
