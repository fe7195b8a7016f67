// `acrolab-studio [TRIAL] [--athlete A] [--video V --calib C [--camera NAME] [--offset-s S]]…
// [--session FILE.acrolab] [--library FILE]`: the workstation window (ui/studio; docs/studio.md).
// Up to four videos: --video, --calib, --camera and --offset-s are given once per video, in the
// same order
// (--camera and --offset-s for all of them or for none).
// `acrolab-studio --video V [--calib C [--camera NAME]] [--athlete A]`: one video analysed alone
// (docs/one-camera.md), its camera from the calibration or from the bed in its first frame.
// `acrolab-studio --live SOURCE… --live-output DIR [--delay S]`: the live mode (docs/live.md).

#include <cstdio>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "acro/studio/studio.h"

int main(int argc, char** argv) {
  CLI::App app{"Acrolab Studio: the workstation window (docs/studio.md)", "acrolab-studio"};
  acro::studio::SessionFiles files;
  std::string session;
  std::vector<std::string> videos, calibrations, cameras;
  std::vector<double> offsets;
  app.add_option("TRIAL", files.trial, "a trial to open: C3D, TRC or CSV");
  app.add_option("--athlete", files.athlete, "the athlete's profile (YAML)")
      ->check(CLI::ExistingFile);
  app.add_option("--video", videos, "a video of the trial (up to four, each with --calib)");
  app.add_option("--calib", calibrations, "the video's camera calibration");
  app.add_option("--camera", cameras, "the camera's name in the calibration");
  app.add_option("--offset-s",
                 offsets,
                 "video time of the trial's first sample (s); default: found from the video");
  app.add_option("--session", session, "a session file (.acrolab) to open");
  std::string library;
  app.add_option("--library",
                 library,
                 "the season library (docs/library.md) for File → Open from library; without a "
                 "trial, its trials are shown to choose one");
  std::vector<std::string> live;
  std::string live_output;
  acro::pipeline::LiveRequest request;  // its defaults are `acrolab live`'s
  double delay_s = 5.0, stall_s = request.source.stall_timeout_s, reconnect_s = request.reconnect_s;
  app.add_option("--live",
                 live,
                 "the live mode: cameras (/dev/video0), stream URLs (udp://, rtsp://, srt://, …) "
                 "or files played at their own pace");
  app.add_option("--live-output", live_output, "the live session's new or empty folder");
  app.add_option("--delay", delay_s, "the live mode's delay (s, 0–60; default 5)")
      ->check(CLI::Range(0.0, 60.0));
  app.add_option("--stall-timeout", stall_s, "a live source silent this long has stopped (s)")
      ->check(CLI::Range(0.1, 3600.0));
  app.add_option("--reconnect",
                 reconnect_s,
                 "a live source that stopped is waited for this long (s; 0: not waited for)")
      ->check(CLI::Range(0.0, 86400.0));
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e);
  }
  const auto fail = [](const std::string& line) {
    std::fprintf(stderr, "acrolab-studio: %s\n", line.c_str());
    return 2;
  };
  if (live.empty())
    for (const char* option : {"--live-output", "--delay", "--stall-timeout", "--reconnect"})
      if (app.count(option) > 0) return fail(std::string(option) + " goes with --live");
  if (!live.empty()) {
    if (live_output.empty()) return fail("--live needs --live-output, the session's folder");
    if (app.count("--offset-s") > 0) return fail("--offset-s is for a trial's video, not --live");
    if (!files.trial.empty() || !videos.empty() || !session.empty())
      return fail("--live opens the live mode alone: no trial, video or session with it");
    request.sources = live;
    request.out_dir = live_output;
    // --calib C [--camera N]: the cameras' intrinsics (their poses found on the bed).
    if (calibrations.size() > 1 || cameras.size() > 1)
      return fail("--live takes one --calib (the cameras' intrinsics) and at most one --camera");
    if (!cameras.empty() && calibrations.empty()) return fail("--camera names a camera of --calib");
    if (!calibrations.empty()) request.intrinsics = calibrations[0];
    if (!cameras.empty()) request.camera = cameras[0];
    request.source.stall_timeout_s = stall_s;
    request.reconnect_s = reconnect_s;
    std::string why;
    if (!request.IsValid(&why)) return fail(why);
    // (--library without --athlete: the athlete is chosen on the window's screen, from the
    // library's athletes)
    return acro::studio::RunStudioLive(argc, argv, request, delay_s, files.athlete, library);
  }
  // No trial and one video: the video analysed alone, its camera from --calib or from the bed.
  const bool alone = files.trial.empty() && session.empty() && videos.size() == 1;
  if (alone && !offsets.empty()) return fail("--offset-s is for a trial's video");
  if (alone && calibrations.empty() && !cameras.empty())
    return fail("--camera names a camera of --calib (without it the camera comes from the bed)");
  if (videos.size() != calibrations.size() && !(alone && calibrations.empty()))
    return fail("--video and --calib go together: " + std::to_string(videos.size()) + " videos, " +
                std::to_string(calibrations.size()) + " calibrations");
  if (files.trial.empty() && session.empty() && videos.size() > 1)
    return fail("several videos go with a trial (one video alone is analysed by itself)");
  if (videos.size() > size_t(acro::studio::kMaxVideos))
    return fail(std::to_string(videos.size()) + " videos: at most 4");
  if (!cameras.empty() && cameras.size() != videos.size())
    return fail("--camera: one per video or none");
  if (!offsets.empty() && offsets.size() != videos.size())
    return fail("--offset-s: one per video or none");
  for (size_t k = 0; k < videos.size(); ++k) {
    acro::studio::VideoFiles v;
    v.video = videos[k];
    if (k < calibrations.size()) v.calibration = calibrations[k];
    if (!cameras.empty()) v.camera = cameras[k];
    if (!offsets.empty()) v.offset_s = offsets[k];
    files.videos.push_back(v);
  }
  return acro::studio::RunStudio(argc, argv, files, session, library);
}
