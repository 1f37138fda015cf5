// TBB before Qt: Qt's `emit` macro would rename a TBB function.
#include <tbb/task_arena.h>
#include <tbb/task_scheduler_observer.h>

#include "job_runner.h"

#include <sys/resource.h>
#include <sys/syscall.h>
#include <unistd.h>

#include <QCoreApplication>
#include <QElapsedTimer>
#include <QMetaObject>
#include <QPointer>
#include <QThread>
#include <atomic>
#include <mutex>

#include "relume/geometry/error.h"
#include "relume/geometry/progress.h"

namespace relume {

namespace {

// Background work yields to the UI: every thread that works for a job (the job's own and the TBB
// workers that join its arena) runs at a lower scheduling priority (nice 10), so that the event
// loop keeps answering even when the job keeps every core busy.
void lowerThisThreadsPriority() {
  thread_local bool lowered = false;
  if (lowered) return;
  lowered = true;
  setpriority(PRIO_PROCESS, pid_t(syscall(SYS_gettid)), 10);
}

class BackgroundObserver : public tbb::task_scheduler_observer {
 public:
  explicit BackgroundObserver(tbb::task_arena& arena) : tbb::task_scheduler_observer(arena) { observe(true); }
  ~BackgroundObserver() override { observe(false); }
  void on_scheduler_entry(bool) override { lowerThisThreadsPriority(); }
};

}  // namespace

struct JobRunner::State {
  QThread* thread = nullptr;
  Progress* progress = nullptr;  // valid while the worker runs
  std::mutex mutex;
  bool cancelRequested = false;
};

JobRunner::JobRunner(QObject* parent) : QObject(parent), state_(std::make_shared<State>()) {}

JobRunner::~JobRunner() {
  cancel();
  if (state_->thread) {
    state_->thread->wait();
    delete state_->thread;
  }
}

bool JobRunner::busy() const { return state_->thread != nullptr; }

void JobRunner::cancel() {
  std::lock_guard<std::mutex> lock(state_->mutex);
  state_->cancelRequested = true;
  if (state_->progress) state_->progress->cancel();
}

bool JobRunner::start(const QString& title, Work work) {
  if (busy()) return false;
  auto st = state_;
  st->cancelRequested = false;
  QPointer<JobRunner> self(this);
  // Throttled progress: at most every 50 ms, always the last word.
  auto lastReport = std::make_shared<QElapsedTimer>();
  lastReport->start();
  st->thread = QThread::create([st, self, work = std::move(work), lastReport]() {
    Progress progress([self, lastReport](double fraction, const std::string& text) {
      if (lastReport->elapsed() < 50 && fraction < 1.0) return;
      lastReport->restart();
      const QString t = QString::fromStdString(text);
      QMetaObject::invokeMethod(
          self.data(), [self, fraction, t]() { if (self) emit self->progressed(fraction, t); }, Qt::QueuedConnection);
    });
    {
      std::lock_guard<std::mutex> lock(st->mutex);
      st->progress = &progress;
      if (st->cancelRequested) progress.cancel();
    }
    Continuation done;
    bool cancelled = false;
    QString message;
    try {
      lowerThisThreadsPriority();
      tbb::task_arena arena;
      arena.initialize();
      BackgroundObserver observer(arena);
      arena.execute([&] { done = work(progress); });
    } catch (const Cancelled&) {
      cancelled = true;
      message = tr("Cancelled; nothing was changed.");
    } catch (const Error& e) {
      message = QString::fromStdString(e.what());
    } catch (const std::exception& e) {
      message = QString::fromStdString(e.what());
    }
    {
      std::lock_guard<std::mutex> lock(st->mutex);
      st->progress = nullptr;
    }
    QMetaObject::invokeMethod(
        self.data(),
        [self, st, done = std::move(done), cancelled, message]() {
          if (!self) return;
          if (st->thread) {
            st->thread->wait();
            delete st->thread;
            st->thread = nullptr;
          }
          bool ok = false;
          QString why = message;
          if (done) {
            try {
              done();
              ok = true;
            } catch (const std::exception& e) {
              why = QString::fromStdString(e.what());
            }
          }
          emit self->finished(ok, cancelled, why);
        },
        Qt::QueuedConnection);
  });
  emit started(title);
  st->thread->start();
  return true;
}

void JobRunner::waitForIdle() {
  while (busy()) {
    QCoreApplication::processEvents(QEventLoop::AllEvents, 20);
    QThread::msleep(5);
  }
}

}  // namespace relume
