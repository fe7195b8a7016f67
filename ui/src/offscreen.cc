#include "acro/ui/offscreen.h"

#include <dlfcn.h>
#include <unistd.h>

#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <map>
#include <mutex>
#include <system_error>

namespace acro::ui {
namespace {

std::string EnvOrEmpty(const char* name) {
  const char* value = std::getenv(name);
  return value ? std::string(value) : std::string();
}

// Xlib entry points, looked up at run time: the check must not need X11 headers or a link-time
// dependency, and VTK has already loaded libX11 into the process anyway.
using XOpenDisplayFn = void* (*)(const char*);
using XQueryExtensionFn = int (*)(void*, const char*, int*, int*, int*);

// The advice when there is no display: use xvfb-run when it is installed, else install it.
std::string NoDisplayAdvice(const std::string& path_var) {
  if (FindOnPath("xvfb-run", path_var)) return "run under xvfb-run -a";
  return "install xvfb and xauth (apt-get install xvfb xauth) and run under xvfb-run -a";
}

}  // namespace

RenderingStatus OffscreenRenderingStatus() {
  const std::string display = EnvOrEmpty("DISPLAY");
  const std::string path_var = EnvOrEmpty("PATH");
  // VTK here is built for X only: no DISPLAY means no rendering (and an abort if we tried).
  if (display.empty()) {
    return {false, "no display (DISPLAY is not set): " + NoDisplayAdvice(path_var)};
  }

  // Xlib, loaded once and never unloaded (the display connections below outlive any call).
  static void* const xlib = dlopen("libX11.so.6", RTLD_LAZY | RTLD_LOCAL);
  if (!xlib) return {false, "cannot load libX11.so.6: " + NoDisplayAdvice(path_var)};
  const auto open_display = reinterpret_cast<XOpenDisplayFn>(dlsym(xlib, "XOpenDisplay"));
  const auto query_extension = reinterpret_cast<XQueryExtensionFn>(dlsym(xlib, "XQueryExtension"));
  if (!open_display || !query_extension) {
    return {false, "libX11.so.6 lacks XOpenDisplay or XQueryExtension"};
  }

  // A display that opened once stays open for the life of the process: when its last client
  // disconnects an X server resets (Xvfb does unless started with -noreset), and a connection made
  // during the reset — VTK's, right after this check — fails or breaks (a crash in XSync).
  static std::mutex mutex;
  static std::map<std::string, void*> connections;
  const std::lock_guard<std::mutex> lock(mutex);
  void*& connection = connections[display];
  if (!connection) connection = open_display(display.c_str());
  if (!connection) {
    return {false, "cannot open display '" + display + "': " + NoDisplayAdvice(path_var)};
  }

  // VTK's X render window needs GLX.
  int opcode = 0;
  int event = 0;
  int error = 0;
  if (!query_extension(connection, "GLX", &opcode, &event, &error)) {
    return {false, "display '" + display + "' has no GLX extension: " + NoDisplayAdvice(path_var)};
  }
  return {true, ""};
}

DisplayEnvironment DisplayEnvironment::FromProcess() {
  return {EnvOrEmpty("DISPLAY"), EnvOrEmpty(kUnderXvfbEnv), EnvOrEmpty("PATH")};
}

std::optional<std::filesystem::path> FindOnPath(std::string_view name, std::string_view path_var) {
  // Walk the ':'-separated list; an empty entry means the current directory (POSIX).
  std::size_t begin = 0;
  while (begin <= path_var.size()) {
    std::size_t end = path_var.find(':', begin);
    if (end == std::string_view::npos) end = path_var.size();
    const std::string_view dir = path_var.substr(begin, end - begin);
    const std::filesystem::path candidate =
        std::filesystem::path(dir.empty() ? "." : std::string(dir)) / std::string(name);
    std::error_code ec;
    if (std::filesystem::is_regular_file(candidate, ec) && access(candidate.c_str(), X_OK) == 0) {
      return candidate;
    }
    begin = end + 1;
  }
  return std::nullopt;
}

std::optional<std::vector<std::string>> XvfbRelaunchCommand(std::span<const std::string> args,
                                                            const DisplayEnvironment& env) {
  // Relaunch only a process that has no display, has not been relaunched already, and can be.
  if (args.empty() || !env.display.empty() || !env.under_xvfb.empty()) return std::nullopt;
  const std::optional<std::filesystem::path> xvfb_run = FindOnPath("xvfb-run", env.path);
  if (!xvfb_run) return std::nullopt;

  // xvfb-run's default screen depth differs between versions: ask for 24-bit colour, and for no
  // server reset when the last client leaves (VTK reconnecting during a reset fails).
  // `env` sets the guard inside the relaunched process, so the command needs no caller setup.
  std::vector<std::string> command = {xvfb_run->string(),
                                      "-a",
                                      "-s",
                                      "-screen 0 1280x1024x24 -noreset",
                                      "env",
                                      std::string(kUnderXvfbEnv) + "=1"};
  command.insert(command.end(), args.begin(), args.end());
  return command;
}

std::optional<std::vector<std::string>> XvfbRelaunchCommand(int argc, const char* const* argv) {
  std::vector<std::string> args(argv, argv + argc);
  // Prefer this executable's absolute path: argv[0] may name a file relative to a directory the
  // relaunched process would not search.
  std::error_code ec;
  const std::filesystem::path self = std::filesystem::read_symlink("/proc/self/exe", ec);
  if (!args.empty() && !ec && !self.empty()) args[0] = self.string();
  return XvfbRelaunchCommand(args, DisplayEnvironment::FromProcess());
}

std::string ExecCommand(const std::vector<std::string>& command) {
  if (command.empty()) return "empty command";
  std::vector<char*> argv;
  argv.reserve(command.size() + 1);
  for (const std::string& arg : command) argv.push_back(const_cast<char*>(arg.c_str()));
  argv.push_back(nullptr);
  execvp(argv[0], argv.data());
  return "cannot run " + command[0] + ": " + std::strerror(errno);
}

}  // namespace acro::ui
