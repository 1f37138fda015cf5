#pragma once
// Progress report and cancellation for long steps: every stage takes a Progress&.
#include <atomic>
#include <functional>
#include <string>

namespace relume {

class Progress {
 public:
  using Callback = std::function<void(double fraction, const std::string& text)>;

  Progress() = default;
  explicit Progress(Callback cb) : callback_(std::move(cb)) {}
  // A sub-stage: fractions map to [lo, hi] of `parent`, cancelling the parent cancels it too.
  Progress(Progress& parent, double lo, double hi);

  // Reports the fraction done in [0,1] of the current stage; throws Cancelled when asked to stop.
  void report(double fraction, const std::string& text);
  // Throws Cancelled when cancellation was requested, and relume::Error when the machine is
  // nearly out of memory (relume/geometry/memory.h).
  void poll() const;
  void cancel() { cancelled_.store(true); }
  // True once this stage or any stage it belongs to was cancelled (a job's Cancel reaches the
  // sub-stage that is waiting on a child process).
  bool cancelled() const;
  // A flag that a signal handler may set (lock-free, async-signal-safe to store to).
  std::atomic<bool>* cancelFlag() { return &cancelled_; }

 private:
  Callback callback_;
  std::atomic<bool> cancelled_{false};
  Progress* parent_ = nullptr;
};
using ProgressScope = Progress;

// A Progress that reports nothing and never cancels.
Progress& silentProgress();

}  // namespace relume
