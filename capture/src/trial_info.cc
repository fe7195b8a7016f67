#include "acro/capture/trial_info.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

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
      << fmt::format("{:g}", trial.point_rate_hz)
      << " Hz = " << fmt::format("{:.3f}", trial.duration_s()) << " s\n";
  out << "Units       "
      << (trial.source.point_units.empty() ? "(none in file)" : trial.source.point_units)
      << " -> m (x" << fmt::format("{:g}", trial.source.point_units_to_m) << ")\n";
  if (!trial.subject_name.empty()) out << "Subject     " << trial.subject_name << "\n";
  out << "Markers     " << gaps.size() << "; marker-frames missing: " << missing_total << " of "
      << static_cast<long long>(gaps.size()) * trial.num_frames << "\n";
  // The names' column as wide as the widest name up to 40 bytes: a longer name is printed whole
  // and pushes its own line only (a 16 MB name padded into every line cost 16 MB a marker).
  constexpr std::size_t kMaxColumn = 40;
  std::size_t width = 0;
  for (const auto& g : gaps) width = std::max(width, std::min(g.label.size(), kMaxColumn));
  for (const auto& g : gaps) {
    out << "  " << g.label << std::string(width - std::min(width, g.label.size()), ' ');
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
    out << " at " << fmt::format("{:g}", trial.analog_rate_hz) << " Hz ("
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
    out << "  #" << i + 1 << " type " << plate.type
        << fmt::format(", centre ({:.3f}, {:.3f}, {:.3f}) m, peak |Fz| {:.1f} N\n",
                       centre.x(),
                       centre.y(),
                       centre.z(),
                       PeakVerticalForce(plate));
  }
  out << "Events      " << trial.events.size() << "\n";
  for (const auto& e : trial.events) {
    out << "  " << fmt::format("{:>8.4f}", e.time_s) << " s  "
        << (e.context.empty() ? "" : e.context + " ") << e.label << "\n";
  }
  out << "Warnings    " << trial.warnings.size() << "\n";
  for (const auto& w : trial.warnings) out << "  " << w << "\n";
  return out.str();
}

std::string FormatTrialInfoJson(const Trial& trial) {
  using Json = nlohmann::ordered_json;  // keys in the order written
  const std::vector<MarkerGaps> gaps = CalcMarkerGaps(trial);
  long long missing_total = 0;
  for (const auto& g : gaps) missing_total += g.missing_frames;

  // File, sampling and markers.
  Json j;
  j["file"] = trial.source.path;
  j["format"] = trial.source.format;
  j["processor"] = trial.source.processor;
  j["point_storage"] = trial.source.point_storage;
  j["frames"] = trial.num_frames;
  j["first_frame"] = trial.first_frame;
  j["point_rate_hz"] = trial.point_rate_hz;
  j["duration_s"] = trial.duration_s();
  j["point_units"] = trial.source.point_units;
  j["subject"] = trial.subject_name;
  j["markers"] = gaps.size();
  j["marker_labels"] = Json::array();
  for (const auto& g : gaps) j["marker_labels"].push_back(g.label);
  j["points"] = trial.num_points();
  j["missing_marker_frames_total"] = missing_total;
  j["gaps"] = Json::array();
  for (const auto& g : gaps) {
    j["gaps"].push_back({{"label", g.label},
                         {"missing_frames", g.missing_frames},
                         {"longest_gap_frames", g.longest_gap_frames},
                         {"gap_count", g.gap_count}});
  }

  // Analog channels and force plates.
  j["analog_rate_hz"] = trial.analog_rate_hz;
  j["analog_samples_per_frame"] = trial.analog_samples_per_frame();
  j["analog_channels"] = Json::array();
  for (const auto& c : trial.analog_channels) {
    j["analog_channels"].push_back(
        {{"label", c.label}, {"unit", c.unit}, {"description", c.description}});
  }
  j["force_plates"] = Json::array();
  for (const ForcePlate& plate : trial.force_plates) {
    Json corners = Json::array();
    for (int c = 0; c < 4; ++c) {
      corners.push_back(
          {plate.corners_W_m(0, c), plate.corners_W_m(1, c), plate.corners_W_m(2, c)});
    }
    j["force_plates"].push_back(
        {{"type", plate.type},
         {"channels", plate.channels},
         {"corners_W_m", std::move(corners)},
         {"origin_F_m", {plate.origin_F_m.x(), plate.origin_F_m.y(), plate.origin_F_m.z()}},
         {"peak_vertical_force_N", PeakVerticalForce(plate)}});
  }

  // Events and warnings.
  j["events"] = Json::array();
  for (const auto& e : trial.events) {
    Json event = {{"label", e.label}, {"context", e.context}, {"time_s", e.time_s}};
    if (!e.description.empty()) event["description"] = e.description;
    j["events"].push_back(std::move(event));
  }
  j["warnings"] = trial.warnings;
  // Labels and descriptions come from the file: bytes that are not UTF-8 become U+FFFD.
  return j.dump(2, ' ', false, Json::error_handler_t::replace) + "\n";
}

}  // namespace acro::capture
