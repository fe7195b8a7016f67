#pragma once

// The workstation window as a program (`acrolab-studio`, docs/studio.md): the window's widgets are
// internal to ui/studio (Qt stays behind this header); the program hands over what to open.

#include <string>

#include "acro/studio/session.h"

namespace acro::studio {

/// Runs the window until it is closed: opens `session_file` (an `.acrolab` file) when given, else
/// `files` when they name a trial, else — with `library` given — that season library's trials to
/// choose one (File → Open from library uses `library`, or the default library). `argc`/`argv` go
/// to Qt. Returns the application's exit code.
int RunStudio(int argc,
              char** argv,
              const SessionFiles& files,
              const std::string& session_file,
              const std::string& library = "");

}  // namespace acro::studio
