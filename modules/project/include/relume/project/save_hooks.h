#pragma once
// Test seam of the project writer (not for applications): every file-system step of a save calls
// saveStep, so that a test can end the process there ("a crash") and check that the user's path
// still opens. `exchange` false forces the fallback without an atomic directory exchange.
//
// Outside tests, RELUME_CRASH_AT_SAVE_STEP=N in the environment makes the N-th step of the
// process's saves kill the process (SIGKILL, as kill -9 would): what scripts use to crash a real
// command, e.g. `relume preprocess -o EXISTING`, at every step in turn; RELUME_SAVE_NO_EXCHANGE
// makes saves take the fallback of two renames (what a file system without an atomic directory
// exchange gets).
// RELUME_SAVE_SNAPSHOTS=DIR copies, at every step, the project's path and the folders a save keeps
// beside it into DIR/<step>/: what a crash at each step would leave, from one uninterrupted run.
#include <functional>

namespace relume::detail {

struct SaveTestHooks {
  std::function<void(const char* step)> step;
  bool exchange = true;
};
// Replaces the hooks (empty by default); returns the previous ones.
SaveTestHooks setSaveTestHooks(SaveTestHooks hooks);

// One file-system step of a save has been done (`what` names it): runs the test hook and counts
// the step for RELUME_CRASH_AT_SAVE_STEP. The writers of a project's files call it after each.
void saveStep(const char* what);

}  // namespace relume::detail
