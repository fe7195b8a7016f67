#pragma once

// A thread joined when the scope ends however it ends: a test whose assertion fails and returns
// while a helper thread (a stream's sender) still runs must not end in std::terminate.

#include <thread>

namespace acro::testing {

class JoinOnExit {
 public:
  explicit JoinOnExit(std::thread& thread) : thread_(thread) {}
  ~JoinOnExit() {
    if (thread_.joinable()) thread_.join();
  }
  JoinOnExit(const JoinOnExit&) = delete;
  JoinOnExit& operator=(const JoinOnExit&) = delete;

 private:
  std::thread& thread_;
};

}  // namespace acro::testing
