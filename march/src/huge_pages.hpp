// Large buffers about to be filled whole, on the kernel's 2 MiB pages where it allows them: their first touch
// faults once per 2 MiB instead of once per 4 KiB (under a hypervisor a fault costs microseconds).
#pragma once

#include <cstddef>

namespace marchcheck::march {

// Asks for transparent huge pages (madvise) on the 2 MiB-aligned pages inside [data, data + bytes), before any of
// them is touched. Nothing where the kernel has them off or the span holds no whole 2 MiB page.
void advise_huge_pages(void* data, std::size_t bytes);

}  // namespace marchcheck::march
