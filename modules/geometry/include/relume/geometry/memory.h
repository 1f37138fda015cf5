#pragma once
// The machine's memory as a limit Relume respects: a step that would need more than is left gives
// a clear relume::Error naming what needed it, never the system's out-of-memory kill. Two guards:
// before a large allocation whose size is known (an image, a texture set), requireMemory; during
// steps whose memory grows as they go (radiosity refinement, the preprocess), Progress::poll
// checks that the machine still has its reserve left (at most every 100 ms).
#include <cstddef>
#include <string>

namespace relume {

// What the kernel reports as available to new allocations (/proc/meminfo MemAvailable), in bytes;
// SIZE_MAX where that is unknown.
size_t availableMemoryBytes();
// The memory kept free for the rest of the system: 2 % of the machine's, at least 256 MiB.
size_t memoryReserveBytes();
// Throws Error(file, element, ...) when allocating `bytes` for `what` would leave less than the
// reserve.
void requireMemory(size_t bytes, const std::string& what, const std::string& file, const std::string& element = "");
// Throws Error when less than the reserve is left (checked at most every 100 ms; Progress::poll
// calls it).
void checkMemoryLeft();

namespace detail {
// Test seam: a reserve in bytes in place of the machine's (0 restores it).
void setMemoryReserveForTest(size_t bytes);
}  // namespace detail

}  // namespace relume
