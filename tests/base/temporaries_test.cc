// The interrupt handler's children: stopping the jobs waits until each has done its own clean-up
// (a batch's job removing its temporaries, or finishing the commit it cannot interrupt), kills one
// that does not end in time, leaves the helpers (an Xvfb server) for last, and starts nothing
// afterwards. The race this guards against was
// seen: a batch stopped by SIGTERM exited while a job was still committing, and the library grew
// by one trial after its parent had gone (tests/app/library_season).

#include "acro/base/temporaries.h"

#include <gtest/gtest.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <thread>
#include <vector>

#include "refdata.h"

extern char** environ;

namespace acro {
namespace {

namespace fs = std::filesystem;

// Starts `sh -c script` as a registered child.
std::unique_ptr<ScopedChildProcess> StartShell(const std::string& script,
                                               ChildRole role = ChildRole::kJob) {
  return ScopedChildProcess::Start(
      [&] {
        std::vector<std::string> words = {"/bin/sh", "-c", script};
        std::vector<char*> argv;
        for (std::string& w : words) argv.push_back(w.data());
        argv.push_back(nullptr);
        pid_t pid = 0;
        return posix_spawn(&pid, argv[0], nullptr, nullptr, argv.data(), environ) == 0 ? pid
                                                                                       : pid_t(-1);
      },
      role);
}

// Waits until `path` exists (the shell has installed its trap once it writes it).
bool AppearsWithin(const fs::path& path, std::chrono::milliseconds timeout) {
  const auto deadline = std::chrono::steady_clock::now() + timeout;
  while (!fs::exists(path)) {
    if (std::chrono::steady_clock::now() > deadline) return false;
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  return true;
}

TEST(Temporaries, StoppingWaitsForTheJobsCleanUpKillsTheStuckAndLeavesTheHelpersForLast) {
  const fs::path dir = acro::testing::ScratchDir("temporaries");
  // A job that takes 0.4 s to clean up after SIGTERM, then writes `done`.
  const fs::path ready = dir / "ready", done = dir / "done";
  const auto slow =
      StartShell("trap 'sleep 0.4; touch " + done.string() + "; exit 0' TERM; touch " +
                 ready.string() + "; while :; do sleep 0.05; done");
  ASSERT_TRUE(slow);
  // A job that ignores SIGTERM.
  const fs::path stubborn_ready = dir / "stubborn_ready";
  const auto stubborn = StartShell("trap '' TERM; touch " + stubborn_ready.string() +
                                   "; while :; do sleep 0.05; done");
  ASSERT_TRUE(stubborn);
  // A helper (an X server, say), which the jobs' stop leaves running.
  const fs::path helper_ready = dir / "helper_ready";
  const auto helper = StartShell(
      "touch " + helper_ready.string() + "; while :; do sleep 0.05; done", ChildRole::kHelper);
  ASSERT_TRUE(helper);
  ASSERT_TRUE(AppearsWithin(ready, std::chrono::seconds(10)));
  ASSERT_TRUE(AppearsWithin(stubborn_ready, std::chrono::seconds(10)));
  ASSERT_TRUE(AppearsWithin(helper_ready, std::chrono::seconds(10)));

  const auto start = std::chrono::steady_clock::now();
  EXPECT_EQ(StopRegisteredChildren(ChildRole::kJob, 1500), 2);
  const double waited_s =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  // The slow job finished its clean-up before the call returned; the stubborn one held it up to
  // the timeout and was killed.
  EXPECT_TRUE(fs::exists(done));
  EXPECT_GE(waited_s, 1.4);
  EXPECT_LT(waited_s, 5.0);
  int status = 0;
  ASSERT_EQ(waitpid(slow->pid(), &status, 0), slow->pid());
  EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0);
  ASSERT_EQ(waitpid(stubborn->pid(), &status, 0), stubborn->pid());
  EXPECT_TRUE(WIFSIGNALED(status) && WTERMSIG(status) == SIGKILL);
  EXPECT_EQ(waitpid(helper->pid(), &status, WNOHANG), 0);  // still running

  // Nothing starts any more.
  bool called = false;
  EXPECT_FALSE(ScopedChildProcess::Start(
      [&] {
        called = true;
        return pid_t(-1);
      },
      ChildRole::kJob));
  EXPECT_FALSE(called);

  // The helper is signalled, not waited for.
  EXPECT_EQ(StopRegisteredChildren(ChildRole::kHelper, 1500), 1);
  ASSERT_EQ(waitpid(helper->pid(), &status, 0), helper->pid());
  EXPECT_TRUE(WIFSIGNALED(status) && WTERMSIG(status) == SIGTERM);
  fs::remove_all(dir);
}

// A file made for a job is registered in the same step (the interrupt handler cannot find it made
// and unregistered: a batch stopped by SIGTERM under load once left its job's stderr file), and
// once the handler has removed the temporaries nothing new is made. Run in a fresh process (the
// handler's removal is for good).
TEST(Temporaries, AFileIsMadeAndRegisteredInOneStepAndNothingAfterTheRemoval) {
  GTEST_FLAG_SET(death_test_style, "threadsafe");
  const fs::path dir = acro::testing::ScratchDir("temporaries_create");
  EXPECT_EXIT(
      {
        std::string pattern = (dir / "job-XXXXXX").string();
        std::unique_ptr<ScopedTemporary> registered;
        const int fd = ScopedTemporary::CreateFile(pattern, &registered);
        bool ok = fd >= 0 && registered != nullptr && fs::exists(pattern) &&
                  pattern.find("XXXXXX") == std::string::npos;
        if (fd >= 0) close(fd);
        ok = ok && RemoveRegisteredTemporaries() == 1 && !fs::exists(pattern);
        std::string again = (dir / "job-XXXXXX").string();
        std::unique_ptr<ScopedTemporary> none;
        ok = ok && ScopedTemporary::CreateFile(again, &none) == -1 && errno == ECANCELED &&
             none == nullptr && fs::is_empty(dir);
        std::exit(ok ? 0 : 1);
      },
      ::testing::ExitedWithCode(0),
      "");
  fs::remove_all(dir);
}

}  // namespace
}  // namespace acro
