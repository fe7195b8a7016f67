#pragma once

// The X display the 3D views render through. Debian's VTK renders only through X (its OpenGL
// window is GLX: no EGL or OSMesa build), so a command that renders with no display starts its own
// Xvfb server here, on a display number the server picks (-displayfd), and stops it when done —
// also on SIGINT and SIGTERM, through the registry of base/temporaries.h, and when this process
// dies without a chance to clean up (the server gets SIGTERM as its parent dies). Nothing is
// re-executed under xvfb-run (docs/design.md, "Rendering without a display").

#include <memory>
#include <string>

namespace acro::ui {

class XDisplay {
 public:
  /// The display in $DISPLAY when an X server answers there; otherwise an Xvfb server started for
  /// this object's lifetime, with $DISPLAY pointing at it. Throws acro::InputError in one line when
  /// there is no display and no Xvfb to start ("install the xvfb package"), or when Xvfb does not
  /// start within 10 s.
  XDisplay();
  ~XDisplay();
  XDisplay(const XDisplay&) = delete;
  XDisplay& operator=(const XDisplay&) = delete;

  /// ":0", ":99", …
  const std::string& name() const;
  /// True when this object started the server (and will stop it).
  bool started_here() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// True when an X server answers on `display_name` (e.g. ":0"); for the tests.
bool XServerAnswers(const std::string& display_name);

}  // namespace acro::ui
