#pragma once

#include <filesystem>
#include <optional>
#include <span>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

namespace acro::ui {

/// Environment variable set (to "1") in a process that was relaunched under Xvfb, so that it does
/// not relaunch itself again.
inline constexpr const char* kUnderXvfbEnv = "ACRO_UNDER_XVFB";

/// Thrown when this process cannot render (no display, no GLX). what() is one line saying what
/// is missing and how to get it.
class RenderingUnavailable : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// Whether VTK can render offscreen in this process, and if not, why.
struct RenderingStatus {
  bool available = false;
  std::string reason;  ///< One line when not available, e.g. "no display: run under xvfb-run -a …".
};

/// Checks, without creating a render window, whether VTK can render here. Debian 12's VTK 9.1 is
/// built for X only (no EGL, no OSMesa): it needs an X display with the GLX extension, and creating
/// a render window without one aborts the process. This opens the display named by DISPLAY through
/// Xlib (which returns an error rather than aborting) and checks that it offers GLX. A display
/// that opens is kept open for the life of the process (an X server resets when its last client
/// leaves, and VTK connecting during that reset crashes).
RenderingStatus OffscreenRenderingStatus();

/// The parts of a process environment that decide whether to relaunch under Xvfb.
struct DisplayEnvironment {
  std::string display;     ///< $DISPLAY.
  std::string under_xvfb;  ///< $ACRO_UNDER_XVFB.
  std::string path;        ///< $PATH.

  /// Read from this process's environment.
  static DisplayEnvironment FromProcess();
};

/// The first executable regular file named `name` in the ':'-separated directory list `path_var`.
std::optional<std::filesystem::path> FindOnPath(std::string_view name, std::string_view path_var);

/// The command to run instead of `args` (args[0] = this program) so that it gets a virtual display:
///   <xvfb-run> -a -s "-screen 0 1280x1024x24 -noreset" env ACRO_UNDER_XVFB=1 args…
/// when DISPLAY is empty, ACRO_UNDER_XVFB is not set and xvfb-run is found on PATH; nothing
/// otherwise (a display exists, we are already the relaunched process, or Xvfb is not installed —
/// then OffscreenRenderingStatus() says why and how to fix it). Pure: reads only `env` and the
/// directories on env.path.
std::optional<std::vector<std::string>> XvfbRelaunchCommand(std::span<const std::string> args,
                                                            const DisplayEnvironment& env);

/// The same for main()'s arguments and this process's environment; args[0] is replaced by this
/// executable's absolute path when /proc/self/exe resolves.
std::optional<std::vector<std::string>> XvfbRelaunchCommand(int argc, const char* const* argv);

/// Replaces this process by `command` (execvp). Returns only on failure, with a one-line reason.
std::string ExecCommand(const std::vector<std::string>& command);

}  // namespace acro::ui
