#pragma once

// The workstation window as a program (`acrolab-studio`, docs/studio.md): the window's widgets are
// internal to ui/studio (Qt stays behind this header); the program hands over what to open.

#include <string>

#include "acro/pipeline/live.h"
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

/// Runs the live mode (docs/live.md) until its window is closed: `request`'s sources watched and
/// recorded into its folder (pipeline::RunLive), shown `delay_s` late, every routine replayed as it
/// is cut and analysed by the `acrolab` program beside this one (for `athlete`, stored in
/// `library` when given); on a second screen when there is one.
int RunStudioLive(int argc,
                  char** argv,
                  const pipeline::LiveRequest& request,
                  double delay_s,
                  const std::string& athlete = "",
                  const std::string& library = "");

}  // namespace acro::studio
