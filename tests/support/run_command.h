#pragma once

// Running a command line as a user does, for the command-line tests: its exit status, stdout and
// stderr kept apart.

#include <sys/wait.h>

#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <sstream>
#include <string>

#include "refdata.h"

namespace acro::testing {

struct ProcessResult {
  int status = -1;
  std::string out;  // stdout
  std::string err;  // stderr
};

/// Runs a shell command line, capturing stdout and stderr separately.
inline ProcessResult Execute(const std::string& command_line) {
  const auto err_path = TempDir() / ("stderr_" + std::to_string(::getpid()) + ".txt");
  const std::string full = command_line + " 2>" + err_path.string();
  ProcessResult run;
  FILE* pipe = popen(full.c_str(), "r");
  if (!pipe) return run;
  std::array<char, 4096> buffer;
  std::size_t n;
  while ((n = fread(buffer.data(), 1, buffer.size(), pipe)) > 0) run.out.append(buffer.data(), n);
  const int raw = pclose(pipe);
  run.status = WIFEXITED(raw) ? WEXITSTATUS(raw) : -1;
  std::ifstream err(err_path);
  run.err.assign(std::istreambuf_iterator<char>(err), {});
  return run;
}

/// A path quoted for the shell.
inline std::string Quote(const std::filesystem::path& p) {
  return "'" + p.string() + "'";
}

/// The last non-empty line of a program's output: the error or warning a user reads.
inline std::string LastLine(const std::string& text) {
  std::string line, last;
  std::istringstream in(text);
  while (std::getline(in, line))
    if (!line.empty()) last = line;
  return last;
}

}  // namespace acro::testing
