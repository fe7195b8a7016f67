#include "acro/capture/trial_info.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>

#include "acro/base/json_writer.h"

namespace acro::capture {
namespace {

const char* PointTypeName(PointType type) {
  switch (type) {
    case PointType::kMarker:
      return "marker";
    case PointType::kAngle:
      return "angle";
    case PointType::kForce:
      return "force";
    case PointType::kMoment:
      return "moment";
    case PointType::kPower:
      return "power";
    case PointType::kScalar:
      return "scalar";
    case PointType::kReaction:
      return "reaction";
  }
  return "unknown";
}

std::string Printf(const char* format, double value) {
  char buffer[64];
  std::snprintf(buffer, sizeof(buffer), format, value);
  return buffer;
}

// Peak magnitude of the vertical ground reaction of a plate over the trial (N), or NaN.
double PeakVerticalForce(const ForcePlate& plate) {
  if (plate.force_W_N.cols() == 0) return std::nan("");
  double peak = 0.0;
  for (std::int64_t i = 0; i < plate.force_W_N.cols(); ++i) {
    const double fz = std::abs(plate.force_W_N(2, i));
    if (std::isfinite(fz)) peak = std::max(peak, fz);
  }
  return peak;
}

}  // namespace

std::vector<MarkerGaps> CalcMarkerGaps(const Trial& trial) {
  std::vector<MarkerGaps> gaps;
  for (int p = 0; p < trial.num_points(); ++p) {
    if (trial.points[p].type != PointType::kMarker) continue;
    MarkerGaps g;
    g.label = trial.points[p].label;
    int run = 0;
    for (int f = 0; f < trial.num_frames; ++f) {
      if (trial.valid(f, p)) {
        run = 0;
        continue;
      }
      ++g.missing_frames;
      if (run++ == 0) ++g.gap_count;
      g.longest_gap_frames = std::max(g.longest_gap_frames, run);
    }
    gaps.push_back(g);
  }
  return gaps;
}

std::string FormatTrialInfoText(const Trial& trial) {
  std::ostringstream out;
  const std::vector<MarkerGaps> gaps = CalcMarkerGaps(trial);
  long long missing_total = 0;
  for (const auto& g : gaps) missing_total += g.missing_frames;

  out << "File        " << trial.source.path << "\n";
  out << "Format      " << trial.source.format;
  if (!trial.source.processor.empty()) out << ", " << trial.source.processor << " processor";
  if (!trial.source.point_storage.empty()) out << ", " << trial.source.point_storage << " storage";
  out << "\n";
  out << "Frames      " << trial.num_frames << " (first frame " << trial.first_frame << ") at "
      << Printf("%g", trial.point_rate_hz) << " Hz = " << Printf("%.3f", trial.duration_s())
      << " s\n";
  out << "Units       "
      << (trial.source.point_units.empty() ? "(none in file)" : trial.source.point_units)
      << " -> m (x" << Printf("%g", trial.source.point_units_to_m) << ")\n";
  if (!trial.subject_name.empty()) out << "Subject     " << trial.subject_name << "\n";
  out << "Markers     " << gaps.size() << "; marker-frames missing: " << missing_total << " of "
      << static_cast<long long>(gaps.size()) * trial.num_frames << "\n";
  std::size_t width = 0;
  for (const auto& g : gaps) width = std::max(width, g.label.size());
  for (const auto& g : gaps) {
    out << "  " << g.label << std::string(width - g.label.size(), ' ');
    if (g.missing_frames == 0) {
      out << "  complete\n";
    } else {
      out << "  missing " << g.missing_frames << " frames in " << g.gap_count
          << (g.gap_count == 1 ? " gap" : " gaps") << ", longest " << g.longest_gap_frames << "\n";
    }
  }
  const int others = trial.num_points() - static_cast<int>(gaps.size());
  if (others > 0) {
    out << "Other points " << others << " (model outputs):";
    for (const auto& p : trial.points) {
      if (p.type != PointType::kMarker)
        out << " " << p.label << "[" << PointTypeName(p.type) << "]";
    }
    out << "\n";
  }
  out << "Analog      " << trial.num_analog_channels()
      << (trial.num_analog_channels() == 1 ? " channel" : " channels");
  if (trial.num_analog_channels() > 0) {
    out << " at " << Printf("%g", trial.analog_rate_hz) << " Hz ("
        << trial.analog_samples_per_frame() << " per frame)";
  }
  out << "\n";
  for (const auto& c : trial.analog_channels) {
    out << "  " << c.label << " [" << (c.unit.empty() ? "-" : c.unit) << "]";
    if (!c.description.empty()) out << "  " << c.description;
    out << "\n";
  }
  out << "Force plates " << trial.force_plates.size() << "\n";
  for (std::size_t i = 0; i < trial.force_plates.size(); ++i) {
    const ForcePlate& plate = trial.force_plates[i];
    const Eigen::Vector3d centre = plate.corners_W_m.rowwise().mean();
    out << "  #" << i + 1 << " type " << plate.type << ", centre (" << Printf("%.3f", centre.x())
        << ", " << Printf("%.3f", centre.y()) << ", " << Printf("%.3f", centre.z())
        << ") m, peak |Fz| " << Printf("%.1f", PeakVerticalForce(plate)) << " N\n";
  }
  out << "Events      " << trial.events.size() << "\n";
  for (const auto& e : trial.events) {
    out << "  " << Printf("%8.4f", e.time_s) << " s  " << (e.context.empty() ? "" : e.context + " ")
        << e.label << "\n";
  }
  out << "Warnings    " << trial.warnings.size() << "\n";
  for (const auto& w : trial.warnings) out << "  " << w << "\n";
  return out.str();
}

std::string FormatTrialInfoJson(const Trial& trial) {
  const std::vector<MarkerGaps> gaps = CalcMarkerGaps(trial);
  long long missing_total = 0;
  for (const auto& g : gaps) missing_total += g.missing_frames;

  JsonWriter w;
  w.BeginObject();
  w.Field("file", trial.source.path);
  w.Field("format", trial.source.format);
  w.Field("processor", trial.source.processor);
  w.Field("point_storage", trial.source.point_storage);
  w.Field("frames", trial.num_frames);
  w.Field("first_frame", static_cast<std::int64_t>(trial.first_frame));
  w.Field("point_rate_hz", trial.point_rate_hz);
  w.Field("duration_s", trial.duration_s());
  w.Field("point_units", trial.source.point_units);
  w.Field("subject", trial.subject_name);
  w.Field("markers", static_cast<int>(gaps.size()));
  w.Key("marker_labels");
  w.BeginArray();
  for (const auto& g : gaps) w.Value(g.label);
  w.EndArray();
  w.Field("points", trial.num_points());
  w.Field("missing_marker_frames_total", static_cast<std::int64_t>(missing_total));
  w.Key("gaps");
  w.BeginArray();
  for (const auto& g : gaps) {
    w.BeginObject();
    w.Field("label", g.label);
    w.Field("missing_frames", g.missing_frames);
    w.Field("longest_gap_frames", g.longest_gap_frames);
    w.Field("gap_count", g.gap_count);
    w.EndObject();
  }
  w.EndArray();
  w.Field("analog_rate_hz", trial.analog_rate_hz);
  w.Field("analog_samples_per_frame", trial.analog_samples_per_frame());
  w.Key("analog_channels");
  w.BeginArray();
  for (const auto& c : trial.analog_channels) {
    w.BeginObject();
    w.Field("label", c.label);
    w.Field("unit", c.unit);
    w.Field("description", c.description);
    w.EndObject();
  }
  w.EndArray();
  w.Key("force_plates");
  w.BeginArray();
  for (const ForcePlate& plate : trial.force_plates) {
    w.BeginObject();
    w.Field("type", plate.type);
    w.Key("channels");
    w.Array(plate.channels);
    w.Key("corners_W_m");
    w.BeginArray();
    for (int c = 0; c < 4; ++c) {
      w.Array(std::vector<double>{
          plate.corners_W_m(0, c), plate.corners_W_m(1, c), plate.corners_W_m(2, c)});
    }
    w.EndArray();
    w.Key("origin_F_m");
    w.Array(std::vector<double>{plate.origin_F_m.x(), plate.origin_F_m.y(), plate.origin_F_m.z()});
    w.Field("peak_vertical_force_N", PeakVerticalForce(plate));
    w.EndObject();
  }
  w.EndArray();
  w.Key("events");
  w.BeginArray();
  for (const auto& e : trial.events) {
    w.BeginObject();
    w.Field("label", e.label);
    w.Field("context", e.context);
    w.Field("time_s", e.time_s);
    if (!e.description.empty()) w.Field("description", e.description);
    w.EndObject();
  }
  w.EndArray();
  w.Key("warnings");
  w.BeginArray();
  for (const auto& message : trial.warnings) w.Value(message);
  w.EndArray();
  w.EndObject();
  return w.str() + "\n";
}

}  // namespace acro::capture
