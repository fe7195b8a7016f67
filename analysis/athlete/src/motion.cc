#include "acro/athlete/motion.h"

#include <algorithm>
#include <cmath>
#include <map>

namespace acro::analysis {

std::vector<std::string> MakeCoordinateNames(const dynamics::Model<double>& model) {
  // Anatomical names of the standard human's joints, axis by axis in sequence order.
  static const std::map<std::string, std::pair<std::string, std::vector<std::string>>> kJoints = {
      {"thorax", {"lumbar", {"flexion", "bending", "rotation"}}},
      {"head", {"neck", {"flexion", "bending", "rotation"}}},
      {"upper_arm", {"shoulder", {"flexion", "rotation", "abduction"}}},
      {"forearm", {"elbow", {"flexion", "pronation"}}},
      {"hand", {"wrist", {"flexion", "deviation"}}},
      {"thigh", {"hip", {"flexion", "rotation", "abduction"}}},
      {"shank", {"knee", {"flexion"}}},
      {"foot", {"ankle", {"flexion", "inversion"}}},
  };
  const std::string root = model.segment(0).name;
  std::vector<std::string> names = {root + "_tx",
                                    root + "_ty",
                                    root + "_tz",
                                    root + "_qw",
                                    root + "_qx",
                                    root + "_qy",
                                    root + "_qz"};
  names.resize(static_cast<size_t>(model.nq()));
  for (int s = 1; s < model.num_segments(); ++s) {
    const dynamics::Segment<double>& seg = model.segment(s);
    std::string side, base = seg.name;
    if (base.rfind("l_", 0) == 0 || base.rfind("r_", 0) == 0) {
      side = base.substr(0, 2);
      base = base.substr(2);
    }
    const auto it = kJoints.find(base);
    for (int k = 0; k < seg.num_axes; ++k) {
      std::string name;
      if (it != kJoints.end() && it->second.second.size() == size_t(seg.num_axes))
        name = side + it->second.first + "_" + it->second.second[size_t(k)];
      else
        name = seg.name + "_" + seg.axis_sequence[size_t(k)];
      names[size_t(seg.q_start + k)] = name;
    }
  }
  return names;
}

std::vector<double> SortedFrameRms(const Motion& motion) {
  std::vector<double> v;
  for (const FrameFit& f : motion.fit)
    if (f.valid && std::isfinite(f.rms_m)) v.push_back(f.rms_m);
  std::sort(v.begin(), v.end());
  return v;
}

double Percentile(const std::vector<double>& sorted, double p) {
  if (sorted.empty()) return std::nan("");
  const double pos = std::clamp(p, 0.0, 100.0) / 100.0 * double(sorted.size() - 1);
  const size_t i = static_cast<size_t>(std::floor(pos));
  const size_t j = std::min(i + 1, sorted.size() - 1);
  return sorted[i] + (pos - double(i)) * (sorted[j] - sorted[i]);
}

}  // namespace acro::analysis
