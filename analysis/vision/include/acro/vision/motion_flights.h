#pragma once

/// \file
/// Every jump's take-off and landing from the image motion alone, frame by frame as a live camera
/// sends them (docs/live.md, "Jumps from the picture"): what a hall's screen shows a second after
/// landing, before (or without) the pose detector. The athlete is the largest moving region above
/// the bed (the frame against a background that is the running median of frames sampled over the
/// last seconds); its lowest point is the soles; in the air while it is above the bed's rest line
/// by a clearance, on the bed once back at the line — the rule of the keypoints' flights
/// (image_flights.h) with the silhouette's lowest point for the soles.

#include <array>
#include <cstdint>
#include <deque>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "acro/capture/video.h"
#include "acro/vision/bed_detection.h"
#include "acro/vision/image_flights.h"
#include "acro/vision/silhouette.h"

namespace acro::vision {

struct MotionFlightOptions {
  /// In the air when the soles are this far above the rest line (m at the bed, from the bed's
  /// length in the picture); on the bed at or below the line; between the two the last state holds.
  double clearance_m = 0.08;
  /// Shorter airborne runs are not jumps (a step, a shadow), s.
  double min_flight_s = 0.25;
  /// The background: one frame sampled every 0.6–1.4 × this many seconds (a random step: a fixed
  /// one falls in step with a regular bounce), the median of the last `background_samples` with
  /// the athlete's region of each left out; jumps are looked for once `background_min_samples` are
  /// in (the frames before are kept and looked at then, so that nothing is missed).
  double background_every_s = 0.4;
  int background_samples = 21;
  int background_min_samples = 7;
  /// The athlete's region must cover at least this fraction of the bed's length squared.
  double min_region_fraction = 0.002;
  BackgroundOptions foreground{.threshold = 25, .colour_threshold = 40, .clean_px = 3};
  bool IsValid(std::string* why) const;
};

/// One jump as it lands.
struct MotionJump {
  int number = 0;  ///< 1, 2, … in the order they landed
  double takeoff_s =
      0.0;  ///< stream time, sub-frame (between the last frame on the bed and the next)
  double landing_s = 0.0;
  double time_of_flight_s() const { return landing_s - takeoff_s; }
  int landing_frame = -1;          ///< the first frame back on the bed
  double landing_arrival_s = 0.0;  ///< when that frame arrived (the caller's clock)
  /// The soles' point in the first frame back on the bed, in the full picture's pixels.
  Eigen::Vector2d landing_px = Eigen::Vector2d::Zero();
  /// The soles' highest point above the rest line over the flight (m at the bed's scale).
  double apex_above_bed_m = 0.0;
};

/// Where the athlete was in the last frame looked at (a window draws it over the picture).
struct MotionSighting {
  double time_s = 0.0;  ///< the frame's stream time
  bool found = false;
  Eigen::Vector2d sole_px = Eigen::Vector2d::Zero();  ///< the soles' point, full picture px
  double height_m = 0.0;                              ///< the soles above the rest line
  /// The athlete's region in the full picture's px: x0, y0, x1, y1.
  std::array<double, 4> box_px{};
};

/// Watches one camera's frames (RGB or grey, any size: the bed is given in the full picture's
/// pixels and scaled) for jumps; in colour, a pixel is the athlete where its channel that differs
/// most from the background differs by more than the colour threshold. Feed frames in order; each
/// call returns the jumps that landed with it.
class MotionFlightWatcher {
 public:
  /// `bed`: the bed detected in the full picture (its width_px × height_px); the frames given may
  /// be a scaled copy of that picture. Throws acro::InputError (where "bed") for a bed too small or
  /// seen end-on (RestLineOfBed), std::invalid_argument for invalid options.
  MotionFlightWatcher(const BedDetection& bed, const MotionFlightOptions& options = {});

  std::vector<MotionJump> Add(const capture::VideoFrame& grey, double arrival_s);

  /// True while the athlete is in the air (a jump has taken off and not landed).
  bool in_air() const { return in_air_; }
  /// The stream time of the last frame looked at.
  double last_time_s() const { return last_time_s_; }
  /// Frames looked at / with the athlete found.
  int frames_seen() const { return frames_seen_; }
  int frames_with_athlete() const { return frames_with_athlete_; }
  const BedLine& rest_line() const { return line_; }
  /// The athlete in the frames looked at by the last Add, in order: none while the background is
  /// still being made, then the frames that waited for it and the frame given.
  const std::vector<MotionSighting>& last_sightings() const { return sightings_; }
  /// Metres per pixel of the full picture at the bed (its length in the picture over 4.28 m).
  double metres_per_px() const { return m_per_px_; }

 private:
  struct Sole {
    bool found = false;
    double x_px = 0, y_px = 0;  ///< full picture
    double height_m = 0;        ///< above the rest line
    std::array<int, 4> box{};   ///< the athlete's region x0, y0, x1, y1 (frame px, ends excluded)
  };
  struct BackgroundSample {
    capture::VideoFrame grey;
    bool has_box = false;
    std::array<int, 4> box{};
  };
  Sole FindSole(const capture::VideoFrame& grey, const capture::VideoFrame* before) const;
  Mask Foreground(const capture::VideoFrame& grey) const;
  void BuildBackground();
  int Threshold(const capture::VideoFrame& frame) const;
  std::vector<MotionJump> Step(const capture::VideoFrame& grey, double arrival_s, Sole* found);
  /// The take-off's (landing's) time: the soles' ballistic path over the flight's first (last)
  /// 0.2 s met with the rest line, within a frame of the frames around it.
  double Crossing(bool takeoff, double contact_s, double frame_s) const;
  void Sample(const capture::VideoFrame& grey, const Sole* sole);

  MotionFlightOptions options_;
  BedLine line_;
  double bed_x_min_px_ = 0, bed_x_max_px_ = 0, full_width_px_ = 0;
  double m_per_px_ = 0;
  std::deque<BackgroundSample> samples_;
  std::vector<std::uint8_t> background_;  ///< grey, the frames' size; empty until made
  capture::VideoFrame previous_;          ///< the frame looked at before (what moved since)
  double next_sample_s_ = -1e300;
  std::uint64_t sample_seed_ = 0x9E3779B97F4A7C15ULL;
  std::deque<std::pair<capture::VideoFrame, double>> waiting_;  // before the first background
  bool in_air_ = false;
  BedLine far_;  ///< the bed's far long side
  // The last frame on the bed, and the frames since it with the soles above the bed.
  double last_contact_s_ = 0;
  bool have_contact_ = false;
  struct FlightFrame {
    double t = 0, y_px = 0, line_px = 0, h_m = 0;
  };
  std::vector<FlightFrame> flight_;
  double takeoff_s_ = 0, apex_m_ = 0;
  double last_time_s_ = 0;
  int jumps_ = 0, frames_seen_ = 0, frames_with_athlete_ = 0;
  std::vector<MotionSighting> sightings_;
};

}  // namespace acro::vision
