#include "relume/geometry/progress.h"

#include "relume/geometry/error.h"
#include "relume/geometry/memory.h"

namespace relume {

void Progress::report(double fraction, const std::string& text) {
  poll();
  if (callback_) callback_(fraction, text);
}

Progress::Progress(Progress& parent, double lo, double hi)
    : callback_([&parent, lo, hi](double f, const std::string& text) { parent.report(lo + f * (hi - lo), text); }),
      parent_(&parent) {}

bool Progress::cancelled() const {
  for (const Progress* p = this; p; p = p->parent_)
    if (p->cancelled_.load()) return true;
  return false;
}

void Progress::poll() const {
  if (cancelled_.load()) throw Cancelled();
  if (parent_) parent_->poll();
  else checkMemoryLeft();  // once per poll, at the root
}

Progress& silentProgress() {
  thread_local Progress p;
  return p;
}

}  // namespace relume
