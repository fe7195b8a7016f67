// `acrolab-studio [TRIAL] [--athlete A] [--video V --calib C [--camera NAME] [--offset-s S]]
// [--session FILE.acrolab]`: the workstation window (ui/studio; docs/studio.md).

#include <cstdio>
#include <string>

#include <CLI/CLI.hpp>

#include "acro/studio/studio.h"

int main(int argc, char** argv) {
  CLI::App app{"Acrolab Studio: the workstation window (docs/studio.md)", "acrolab-studio"};
  acro::studio::SessionFiles files;
  std::string session;
  double offset_s = 0;
  app.add_option("TRIAL", files.trial, "a trial to open: C3D, TRC or CSV");
  app.add_option("--athlete", files.athlete, "the athlete's profile (YAML)");
  app.add_option("--video", files.video, "the trial's video");
  app.add_option("--calib", files.calibration, "the video's camera calibration");
  app.add_option("--camera", files.camera, "the camera's name in the calibration");
  CLI::Option* offset = app.add_option("--offset-s",
                                       offset_s,
                                       "video time of the trial's first sample (s); "
                                       "default: found from the video");
  app.add_option("--session", session, "a session file (.acrolab) to open");
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e);
  }
  if (*offset) files.offset_s = offset_s;
  if (files.video.empty() != files.calibration.empty()) {
    std::fprintf(stderr, "acrolab-studio: --video and --calib go together\n");
    return 2;
  }
  return acro::studio::RunStudio(argc, argv, files, session);
}
