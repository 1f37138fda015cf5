#pragma once
// Long work off the UI thread: one job at a time, its progress reported to the UI, cancellable.
// The work runs on a worker thread and returns a continuation that the UI thread runs when the
// work succeeded, so the document changes only on the UI thread and only on success: a failed
// or cancelled job leaves everything as it was.
#include <QObject>
#include <QString>
#include <functional>
#include <memory>

namespace relume {

class Progress;

class JobRunner : public QObject {
  Q_OBJECT
 public:
  using Continuation = std::function<void()>;
  using Work = std::function<Continuation(Progress&)>;

  explicit JobRunner(QObject* parent = nullptr);
  ~JobRunner() override;
  // Starts `work` unless a job runs already (then returns false).
  bool start(const QString& title, Work work);
  void cancel();
  bool busy() const;
  // Blocks until the running job (if any) has ended and its result was delivered.
  void waitForIdle();

 signals:
  void started(const QString& title);
  void progressed(double fraction, const QString& text);
  // ok: the continuation ran; otherwise `message` says why (cancelled, or the library's error).
  void finished(bool ok, bool cancelled, const QString& message);

 private:
  struct State;
  std::shared_ptr<State> state_;
};

}  // namespace relume
