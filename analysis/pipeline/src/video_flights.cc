#include "acro/pipeline/video_flights.h"

#include <cmath>

#include <nlohmann/json.hpp>

#include "acro/fig/score_sheet.h"
#include "acro/pipeline/detect.h"
#include "acro/vision/bed_detection.h"
#include "acro/vision/camera_motion.h"

namespace acro::pipeline {

VideoFlights FindFlightsInVideo(const VideoFlightsRequest& request, const Progress& progress) {
  VideoFlights out;
  out.info = capture::VideoReader(request.video).info();
  // The bed before the detection: a video without one costs no detection.
  const vision::BedLine line = request.bed_line
                                   ? *request.bed_line
                                   : vision::RestLineOfBed(vision::DetectBed(request.video, 0));
  const pose::VideoPoses poses = DetectPosesInCache(request.video, request.model, progress);
  capture::KeypointDetections detections = Body25bDetections(poses);
  detections.source = request.video.string();
  out.flights = vision::FindFlightsInImage(detections, out.info.average_fps, line, request.options);
  // The bed's line is the first frame's: a camera that moved after it is said, per flight.
  for (const std::string& w : vision::CameraMotionWarnings(
           vision::MeasureCameraMotion(request.video, {}, progress), out.flights))
    out.flights.warnings.push_back(w);
  if (out.info.variable_frame_rate)
    out.flights.warnings.push_back(
        "the video's frame rate varies: its frames are timed at the average rate, " +
        std::to_string(out.info.average_fps) + " fps");
  out.time_of_flight_score = fig::TruncateTimeOfFlight(out.flights.TotalTimeOfFlight(), 0.005);
  return out;
}

std::string FormatVideoFlightsJson(const VideoFlights& flights,
                                   const std::filesystem::path& video) {
  const auto number = [](double x) {
    return std::isfinite(x) ? nlohmann::json(x) : nlohmann::json();
  };
  nlohmann::json j;
  j["video"] = std::filesystem::absolute(video).string();
  j["rate_hz"] = flights.flights.rate_hz;
  j["bed_line"] = {{"y0_px", flights.flights.bed.y0_px},
                   {"slope", flights.flights.bed.slope},
                   {"source", flights.flights.bed.source}};
  j["athlete_height_px"] = flights.flights.athlete_height_px;
  nlohmann::json list = nlohmann::json::array();
  int index = 0;
  for (const vision::ImageFlight& f : flights.flights.flights) {
    list.push_back({{"index", ++index},
                    {"partial", f.partial()},
                    {"last_contact_frame", f.last_contact_frame},
                    {"first_contact_frame", f.first_contact_frame},
                    {"takeoff_s", number(f.takeoff_s)},
                    {"landing_s", number(f.landing_s)},
                    {"time_of_flight_s", number(f.time_of_flight_s())},
                    {"apex_s", number(f.apex_s)},
                    {"takeoff_timed_by", f.takeoff_method},
                    {"landing_timed_by", f.landing_method},
                    {"landing_px", {f.landing_px.x(), f.landing_px.y()}}});
  }
  j["flights"] = list;
  j["time_of_flight_sum_s"] = flights.flights.TotalTimeOfFlight();
  j["T"] = flights.time_of_flight_score;
  j["warnings"] = flights.flights.warnings;
  return j.dump(2) + "\n";
}

}  // namespace acro::pipeline
