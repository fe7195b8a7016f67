// What `acrolab video info` prints (docs/cli.md).

#include <fmt/format.h>

#include <nlohmann/json.hpp>

#include "acro/capture/video.h"

namespace acro::capture {

std::string FormatVideoInfoText(const VideoInfo& v) {
  std::string audio;
  for (const std::string& a : v.audio_codecs) audio += (audio.empty() ? "" : ", ") + a;
  std::string out;
  out += fmt::format("File        {}\n", v.path);
  out += fmt::format("Container   {}\n", v.container);
  out += fmt::format("Codec       {}\n", v.codec);
  out += fmt::format("Size        {} x {} as displayed ({} x {} stored, rotated {} deg)\n",
                     v.width,
                     v.height,
                     v.coded_width,
                     v.coded_height,
                     v.rotation_deg);
  out += fmt::format("Frames      {} ({} keyframes)\n", v.num_frames, v.num_keyframes);
  out += fmt::format("Frame rate  {:.3f} fps average, {:.3f} declared, {}\n",
                     v.average_fps,
                     v.nominal_fps,
                     v.variable_frame_rate ? "variable" : "constant");
  out +=
      fmt::format("Duration    {:.3f} s, first frame at {:.3f} s\n", v.duration_s, v.start_time_s);
  out += fmt::format("Audio       {}\n", audio.empty() ? "none" : audio);
  return out;
}

std::string FormatVideoInfoJson(const VideoInfo& v) {
  nlohmann::ordered_json j;
  j["path"] = v.path;
  j["container"] = v.container;
  j["codec"] = v.codec;
  j["width"] = v.width;
  j["height"] = v.height;
  j["coded_width"] = v.coded_width;
  j["coded_height"] = v.coded_height;
  j["rotation_deg"] = v.rotation_deg;
  j["frames"] = v.num_frames;
  j["keyframes"] = v.num_keyframes;
  j["average_fps"] = v.average_fps;
  j["nominal_fps"] = v.nominal_fps;
  j["variable_frame_rate"] = v.variable_frame_rate;
  j["duration_s"] = v.duration_s;
  j["start_time_s"] = v.start_time_s;
  j["audio_tracks"] = v.audio_codecs;
  return j.dump(2, ' ', false, nlohmann::json::error_handler_t::replace) + "\n";
}

}  // namespace acro::capture
