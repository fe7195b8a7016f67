#include "acro/base/interrupts.h"

#include <atomic>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <string>
#include <thread>

#include <pthread.h>
#include <unistd.h>

#include "acro/base/temporaries.h"

namespace acro {
namespace {

// Set by the interrupt thread as soon as a signal arrives, before it stops anything.
std::atomic<bool>& Interrupted() {
  static std::atomic<bool> interrupted{false};
  return interrupted;
}

}  // namespace

void InstallInterruptCleanup() {
  sigset_t signals;
  sigemptyset(&signals);
  sigaddset(&signals, SIGINT);
  sigaddset(&signals, SIGTERM);
  pthread_sigmask(SIG_BLOCK, &signals, nullptr);
  std::thread([signals] {
    int received = 0;
    if (sigwait(&signals, &received) != 0) return;
    Interrupted() = true;
    // A batch's jobs first, waited for (each finishes the commit it may be in and removes its
    // own temporaries); then this program's outputs; the helpers (Xvfb) last, since losing the
    // X server would end this program with status 1 before it has cleaned up.
    StopRegisteredChildren(ChildRole::kJob);
    const int removed = RemoveRegisteredTemporaries();
    // Outputs already moved into place before the signal are whole: kept, and said (a Ctrl-C as a
    // command finishes finds its outputs written).
    const int kept = CommittedOutputs();
    StopRegisteredChildren(ChildRole::kHelper);
    std::fprintf(stderr,
                 "\nacrolab: interrupted (%s); %d unfinished output%s removed%s\n",
                 received == SIGINT ? "SIGINT" : "SIGTERM",
                 removed,
                 removed == 1 ? "" : "s",
                 kept > 0 ? (", " + std::to_string(kept) + " finished kept").c_str() : "");
    std::fflush(stderr);
    _exit(128 + received);
  }).detach();
}

bool InterruptReceived() {
  return Interrupted();
}

int ExitStatusUnlessInterrupted(int status) {
  if (!Interrupted()) return status;
  // The command returned because its work was stopped under it (a batch whose jobs the interrupt
  // thread killed): that thread is still removing the outputs and exits with 128 + the signal.
  // Returning would exit first, with the command's status (a SIGTERMed batch once exited 1), and
  // run the static destructors under the thread's feet.
  for (;;) std::this_thread::sleep_for(std::chrono::seconds(1));
}

}  // namespace acro
