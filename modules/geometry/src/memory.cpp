#include "relume/geometry/memory.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <limits>

#include "relume/geometry/error.h"

namespace relume {

namespace {
std::atomic<size_t> g_testReserve{0};

// A field of /proc/meminfo in bytes (0 when absent).
size_t meminfo(const char* key) {
  std::FILE* f = std::fopen("/proc/meminfo", "r");
  if (!f) return 0;
  char line[256];
  size_t kb = 0;
  const size_t n = std::strlen(key);
  while (std::fgets(line, sizeof line, f))
    if (std::strncmp(line, key, n) == 0 && line[n] == ':') {
      unsigned long long v = 0;
      if (std::sscanf(line + n + 1, "%llu", &v) == 1) kb = size_t(v);
      break;
    }
  std::fclose(f);
  return kb * 1024;
}

std::string gib(size_t bytes) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.2f GiB", double(bytes) / double(1ull << 30));
  return buf;
}
}  // namespace

size_t availableMemoryBytes() {
  const size_t a = meminfo("MemAvailable");
  return a > 0 ? a : std::numeric_limits<size_t>::max();
}

size_t memoryReserveBytes() {
  if (const size_t t = g_testReserve.load()) return t;
  return std::max<size_t>(size_t(256) << 20, meminfo("MemTotal") / 50);
}

void requireMemory(size_t bytes, const std::string& what, const std::string& file, const std::string& element) {
  const size_t avail = availableMemoryBytes(), reserve = memoryReserveBytes();
  if (avail == std::numeric_limits<size_t>::max()) return;
  if (bytes > avail || avail - bytes < reserve)
    throw Error(file, element,
                what + " needs " + gib(bytes) + " of memory and the machine has " + gib(avail) +
                    " available (keeping " + gib(reserve) + " for the rest of the system): nothing was done");
}

void checkMemoryLeft() {
  static std::atomic<int64_t> last{0};
  const int64_t now = std::chrono::duration_cast<std::chrono::milliseconds>(
                          std::chrono::steady_clock::now().time_since_epoch()).count();
  int64_t prev = last.load();
  if (now - prev < 100 && g_testReserve.load() == 0) return;
  if (!last.compare_exchange_strong(prev, now) && g_testReserve.load() == 0) return;
  const size_t avail = availableMemoryBytes(), reserve = memoryReserveBytes();
  if (avail != std::numeric_limits<size_t>::max() && avail < reserve)
    throw Error("", "memory",
                "the machine is nearly out of memory (" + gib(avail) + " left, less than the " + gib(reserve) +
                    " kept for the rest of the system): the step was stopped before the system would kill Relume; "
                    "close other programs or give a smaller input (fewer or smaller photos, a larger --min-area)");
}

void detail::setMemoryReserveForTest(size_t bytes) { g_testReserve.store(bytes); }

}  // namespace relume
