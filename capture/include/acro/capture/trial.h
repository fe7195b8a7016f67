#pragma once

#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "acro/capture/parameter_set.h"

namespace acro::capture {

/// Where a trial came from and how its file stored it, before conversion to SI.
struct SourceInfo {
  std::string path;
  std::string format;         ///< "C3D", "TRC" or "CSV"
  std::string processor;      ///< C3D: "Intel", "DEC" or "MIPS"; empty for text formats
  std::string point_storage;  ///< C3D: "integer" or "float"
  double point_scale = 1.0;   ///< C3D POINT:SCALE as stored (negative for float storage)
  std::string point_units;    ///< the file's length unit, e.g. "mm"; empty if the file had none
  double point_units_to_m = 1e-3;  ///< factor applied to marker coordinates on import
  /// The file's axis convention as written (C3D POINT:X_SCREEN/Y_SCREEN, e.g. "+X +Z"), or empty.
  std::string axis_convention;
  /// C3D header word 6: the largest gap (frames) the recording system interpolated over; 0 if none.
  int max_interpolation_gap = 0;
  /// TRC: the time column's first value (s), as written; 0 for the other formats.
  double first_time_s = 0.0;
};

/// What a point holds. C3D files from Vicon Nexus store model outputs (angles, forces, moments,
/// powers) as points; only markers are lengths converted to metres on import, the others keep the
/// file's units (named in Point::unit).
enum class PointType : std::uint8_t {
  kMarker,
  kAngle,
  kForce,
  kMoment,
  kPower,
  kScalar,
  kReaction
};

struct PointInfo {
  std::string label;
  std::string description;
  PointType type = PointType::kMarker;
  std::string unit;  ///< "m" for markers after import; file unit for the others
};

/// An event on the trial's time line: C3D header events and EVENT group, or text formats' events.
struct Event {
  std::string label;
  std::string context;  ///< e.g. "Left", "Right", "General", or a phase name
  std::string description;
  std::string subject;
  double time_s = 0.0;    ///< seconds from the C3D time origin (frame 1 at t = 0)
  bool displayed = true;  ///< header event display flag
  int icon_id = 0;
  int generic_flag = 0;
};

struct AnalogChannel {
  std::string label;
  std::string description;
  std::string unit;        ///< ANALOG:UNITS, e.g. "V", "N", "Nmm"
  double scale = 1.0;      ///< ANALOG:SCALE of this channel
  double offset = 0.0;     ///< ANALOG:OFFSET of this channel (as decoded: signed or unsigned)
  double gain_code = 0.0;  ///< ANALOG:GAIN if present
};

/// A force platform (C3D FORCE_PLATFORM group, types 1–4) and what it measured.
/// Geometry in W (metres). The plate frame F has its axes along the corners as defined in the C3D
/// manual ("Force platforms"; see force_plate.h). `origin_F_m` is ORIGIN as stored: per the manual
/// the position of the geometric centre of the top surface relative to the transducer origin,
/// expressed in F (z ≤ 0, F's z pointing into the plate); files that store the opposite vector
/// (z > 0) are handled when the outputs are computed.
struct ForcePlate {
  int type = 0;
  Eigen::Matrix<double, 3, 4> corners_W_m = Eigen::Matrix<double, 3, 4>::Zero();
  Eigen::Vector3d origin_F_m = Eigen::Vector3d::Zero();
  std::vector<int> channels;   ///< 0-based analog channel indices, in the type's order
  Eigen::MatrixXd cal_matrix;  ///< CAL_MATRIX (rows = outputs), empty when absent
  std::vector<int> zero;       ///< ZERO: first and last frame of the baseline, 1-based

  /// Ground reaction per analog sample, in W: the force that the plate exerts on the body (N), the
  /// centre of pressure on the plate's top surface (m), the free moment about the plate normal at
  /// the COP (N·m, as a vector in W), and the moment about the plate's transducer origin (N·m).
  /// Samples where the vertical force is too small for a COP hold NaN COP and free moment.
  Eigen::Matrix3Xd force_W_N;
  Eigen::Matrix3Xd cop_W_m;
  Eigen::Matrix3Xd free_moment_W_Nm;
  Eigen::Matrix3Xd moment_at_origin_W_Nm;
};

/// Everything read from a motion-capture file, in SI and the lab frame W (Z up as recorded).
/// Point samples are stored frame-major exactly as C3D lays them out: column f·P + p of
/// `positions` is point p at frame f. Gaps (invalid samples, occlusions) are NaN.
struct Trial {
  SourceInfo source;

  double point_rate_hz = 0.0;
  std::int64_t first_frame = 1;  ///< number of the first frame (C3D numbering starts at 1)
  int num_frames = 0;

  std::vector<PointInfo> points;
  Eigen::Matrix3Xd positions;  ///< 3 × (num_frames·num_points); metres for markers; NaN = gap
  Eigen::ArrayXXf residuals;  ///< num_points × num_frames; C3D residual in file units, −1 = invalid
  Eigen::Array<std::uint8_t, Eigen::Dynamic, Eigen::Dynamic>
      camera_masks;  ///< num_points × num_frames

  double analog_rate_hz = 0.0;
  std::vector<AnalogChannel> analog_channels;
  Eigen::MatrixXd analog;  ///< num_channels × num_samples, scaled to the channels' units

  std::vector<ForcePlate> force_plates;
  std::vector<Event> events;

  std::string subject_name;
  /// Every C3D parameter as read (empty for text formats). Writers keep it so a round trip is
  /// lossless.
  ParameterSet parameters;
  /// Problems that did not stop the import, one line each, naming file, field and value.
  std::vector<std::string> warnings;

  int num_points() const { return static_cast<int>(points.size()); }
  int num_analog_channels() const { return static_cast<int>(analog_channels.size()); }
  std::int64_t num_analog_samples() const { return analog.cols(); }
  /// Analog samples per point frame (C3D: an integer; 0 when there is no analog data).
  int analog_samples_per_frame() const;
  double duration_s() const { return point_rate_hz > 0 ? num_frames / point_rate_hz : 0.0; }

  auto position(int frame, int point) const {
    return positions.col(std::int64_t(frame) * num_points() + point);
  }
  auto position(int frame, int point) {
    return positions.col(std::int64_t(frame) * num_points() + point);
  }
  bool valid(int frame, int point) const {
    return !std::isnan(positions(0, std::int64_t(frame) * num_points() + point));
  }

  /// Index of the point with this label (exact match first, then ignoring a `Subject:` prefix), or
  /// −1.
  int FindPoint(const std::string& label) const;
  /// Index of the analog channel with this label, or −1.
  int FindAnalog(const std::string& label) const;
};

/// The check every trial reader ends with (docs/limits.md, "Trials"), so that none can forget it: a
/// marker coordinate that is not finite, or farther than 10 km from the lab's origin, is no
/// position in a hall. It becomes a gap (NaN, residual −1), and one warning in trial->warnings says
/// how many and where the first is (marker, frame and value). `file` names the trial.
void GapImpossiblePositions(Trial* trial, const std::string& file);

/// What a trial holds that a command can use.
struct TrialContent {
  int frames = 0;
  int markers = 0;             ///< points of type marker
  int markers_with_data = 0;   ///< markers with a position in at least one frame
  int frames_with_data = 0;    ///< frames where at least one marker has a position
};
TrialContent CountContent(const Trial& trial);

/// Throws acro::InputError naming `file` when the trial cannot give `use` what it needs: fewer than
/// `min_frames` frames holding a marker position, or no marker with any position. The message has
/// the counts ("holds 1 frame; analysing it needs at least 2").
void DemandUsableContent(const Trial& trial, const std::string& file, int min_frames,
                         const std::string& use);

/// Turns everything the trial holds in W by R_new_old (a rotation): the points, the force plates'
/// corners and their outputs in W. For a file recorded with another axis up (analysis'
/// OrientTrialUp). The plates' own frames follow their corners.
void RotateTrial(const Eigen::Matrix3d& R_new_old, Trial* trial);

}  // namespace acro::capture
