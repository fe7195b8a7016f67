#pragma once

/// \file
/// Every jump's take-off and landing from one camera's 2D keypoints (docs/one-camera.md, "Flights
/// from the image"): what a force-plate system under the bed gives — time of flight to a few
/// milliseconds — from a phone beside the trampoline. The soles (heels, toes and ankles, the
/// keypoint lowest over five frames, per foot) against the bed's rest line in the picture: in the
/// air while they are above it. Each crossing is timed to a fraction of a frame where the soles'
/// image height crosses the line between the two frames around it, or
/// (ImageFlightOptions::time_from_arc) from the flight's ballistic arc: the parabola of the centre
/// of mass (from the keypoints and de Leva's segment masses) over the flight plus the soles' offset
/// from it.

#include <limits>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "acro/capture/detections.h"
#include "acro/vision/bed_detection.h"

namespace acro::vision {

/// The bed's surface at rest as the picture shows it: a straight line y = y0 + slope · x (px,
/// image y down), where the athlete's soles meet the bed.
struct BedLine {
  double y0_px = 0.0;
  double slope = 0.0;
  std::string source;  ///< "the bed detected in <file> @frame 0", "--bed-line"
  double At(double x_px) const { return y0_px + slope * x_px; }
};

/// The line midway between the detected bed's upper and lower long sides (the middle of the bed
/// across, where a trampolinist lands): for a camera beside the bed, whose picture shows it as a
/// flat quadrilateral. Throws acro::InputError (where "bed") when the quadrilateral is taller than
/// it is wide (a camera at the bed's end or above it: its rest line is not one line).
BedLine RestLineOfBed(const BedDetection& bed);

struct ImageFlightOptions {
  /// Detections below this confidence are not used.
  double min_confidence = 0.3;
  /// In the air when the soles are above the rest line by more than this fraction of the
  /// athlete's height in the picture (its median over the frames where it is upright), and in
  /// contact when at or below the line itself: between the two, the last state holds.
  double clearance_fraction = 0.03;
  /// Shorter airborne runs are not flights (a step, a detection's jitter), s.
  double min_flight_s = 0.2;
  /// Time each crossing from the flight's arc (the centre of mass's parabola + the soles' offset
  /// over the 50 ms next to the crossing) rather than by the soles' linear interpolation between
  /// the two frames around it. Off by default: on the sample routine's side video the hips of a
  /// double back and a full twist leave their parabola as the tuck or the twist starts, and the
  /// arc timed those take-offs 28–31 ms early where the soles' own crossing was within 11 ms
  /// (docs/one-camera.md).
  bool time_from_arc = false;
  /// The arc (and the apex) needs at least this many airborne frames; and its crossing is used
  /// only within a frame (or 20 ms) of the soles' own.
  int min_arc_frames = 6;
  bool IsValid(std::string* why) const;
};

struct ImageFlight {
  /// The soles' last frame on the bed before the flight and first frame back on it (video frames);
  /// −1 when the video starts (ends) in the air.
  int last_contact_frame = -1;
  int first_contact_frame = -1;
  double takeoff_s = 0.0;  ///< video time, sub-frame; NaN when partial at the start
  double landing_s = 0.0;  ///< NaN when partial at the end
  double apex_s = 0.0;     ///< the top of the centre of mass's arc
  /// The centre of mass's downward acceleration in the picture over the flight (px/s², its
  /// parabola's 2·c2; NaN without an arc): gravity seen at the athlete's depth, g·f/Z for a camera
  /// beside the routine — how one camera tells how far away the athlete is (docs/one-camera.md).
  double com_accel_px_s2 = std::numeric_limits<double>::quiet_NaN();
  /// How the crossings were timed: "arc" or "soles" (linear between two frames), per end.
  std::string takeoff_method, landing_method;
  /// The soles' image point at the first contact frame (px).
  Eigen::Vector2d landing_px = Eigen::Vector2d::Zero();
  bool partial() const { return last_contact_frame < 0 || first_contact_frame < 0; }
  double time_of_flight_s() const { return landing_s - takeoff_s; }
};

struct ImageFlights {
  std::vector<ImageFlight> flights;
  BedLine bed;
  double rate_hz = 0.0;
  double athlete_height_px = 0.0;  ///< as measured (the clearance's scale)
  /// Per frame: the soles' lowest image point (x, y), the hips' image y and the centre of mass's
  /// (segments' centres weighted by de Leva's mass fractions; NaN with less than 80 % of the mass
  /// seen) (px, NaN where not seen).
  Eigen::VectorXd sole_x_px, sole_y_px, hip_y_px, com_y_px;
  std::vector<std::string> warnings;
  /// The complete flights' time of flight summed (s): the FIG T before truncation.
  double TotalTimeOfFlight() const;
};

/// The most confident person of a frame (the sum of the confidences at or above
/// `min_confidence`), or −1 for none: the athlete, when the picture also shows a coach or a judge.
int MostConfidentPerson(const std::vector<capture::DetectedPerson>& people, double min_confidence);

/// The flights of the person in `detections` (the most confident one in each frame; BODY_25B,
/// BODY_25, COCO or BlazePose names: hips, ankles, heels and toes found by name) against `bed`, at
/// `rate_hz` frames a second. Throws acro::InputError (where "detections") when no hips or feet
/// keypoints are in the set, or nobody is seen in enough frames to tell the athlete's height.
ImageFlights FindFlightsInImage(const capture::KeypointDetections& detections,
                                double rate_hz,
                                const BedLine& bed,
                                const ImageFlightOptions& options = {});

}  // namespace acro::vision
