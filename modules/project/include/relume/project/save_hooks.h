#pragma once
// Test seam of the project writer (not for applications): called at each file-system step of a
// save, so that a test can end the process there ("a crash") and check that the user's path
// still opens. `exchange` false forces the fallback without an atomic directory exchange.
#include <functional>

namespace relume::detail {

struct SaveTestHooks {
  std::function<void(const char* step)> step;
  bool exchange = true;
};
// Replaces the hooks (empty by default); returns the previous ones.
SaveTestHooks setSaveTestHooks(SaveTestHooks hooks);

}  // namespace relume::detail
