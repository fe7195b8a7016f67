#pragma once

// The window tests' wait: Qt's events handled until a condition holds or the time is up (only
// for tests that link Qt).

#include <QCoreApplication>
#include <QElapsedTimer>
#include <QThread>

#include <functional>

namespace acro::testing {

/// Handles events (at most `slice_ms` at a time, a short sleep between) until `done()` or `ms`
/// have passed; returns `done()`.
inline bool WaitUntil(const std::function<bool()>& done, int ms, int slice_ms = 20) {
  QElapsedTimer t;
  t.start();
  while (!done() && t.elapsed() < ms) {
    QCoreApplication::processEvents(QEventLoop::AllEvents, slice_ms);
    QThread::msleep(slice_ms >= 20 ? 5 : 2);
  }
  return done();
}

}  // namespace acro::testing
