#include "acro/scene/skill_ghost.h"

#include <algorithm>
#include <cmath>
#include <set>
#include <string>

#include <nlohmann/json.hpp>

#include "acro/base/file_io.h"
#include "acro/base/input_error.h"
#include "acro/capture/storage.h"
#include "acro/dynamics/configuration.h"

namespace acro::analysis {

namespace {

using Json = nlohmann::json;
constexpr double kDegToRad = M_PI / 180.0;
constexpr std::int64_t kMaxResultBytes = 64 << 20;

// A field of result.json, checked.
const Json& Field(const Json& j, const std::string& key, const std::string& file) {
  if (!j.contains(key)) throw InputError(file, key, "missing (is this acrolab optimize's result?)");
  return j.at(key);
}

std::vector<double> Numbers(const Json& j, const std::string& key, const std::string& file) {
  const Json& a = Field(j, key, file);
  if (!a.is_array()) throw InputError(file, key, "not a list of numbers");
  std::vector<double> out;
  for (const Json& x : a) {
    if (!x.is_number() || !std::isfinite(x.get<double>()))
      throw InputError(file, key, "holds '" + x.dump() + "', not a number");
    out.push_back(x.get<double>());
  }
  return out;
}

}  // namespace

SkillGhost ReadSkillGhost(const std::filesystem::path& path,
                                const dynamics::Model<double>& model) {
  std::error_code ec;
  if (!std::filesystem::exists(path, ec))
    throw InputError(
        path.string(), "", "no such folder or file (acrolab optimize's output folder)");
  const std::filesystem::path dir = IsDirectory(path) ? path : path.parent_path();
  const std::filesystem::path result_path = dir / "result.json";
  const std::filesystem::path mot_path = dir / "motion.mot";
  const std::string result_file = result_path.string(), mot_file = mot_path.string();

  SkillGhost d;
  {
    const std::vector<std::uint8_t> bytes = ReadFileBytes(result_path, kMaxResultBytes);
    const Json j = Json::parse(bytes.begin(), bytes.end(), nullptr, false);
    if (j.is_discarded() || !j.is_object())
      throw InputError(result_file, "", "not a JSON object (acrolab optimize's result.json)");
    const auto text = [&](const char* key) {
      const Json& v = Field(j, key, result_file);
      if (!v.is_string()) throw InputError(result_file, key, "not a string");
      return v.get<std::string>();
    };
    d.name = text("skill");
    d.fig_code = text("fig_code");
    d.athlete = text("athlete");
    const Json& T = Field(j, "flight_time_s", result_file);
    if (!T.is_number() || !(T.get<double>() > 0) || !std::isfinite(T.get<double>()))
      throw InputError(result_file, "flight_time_s", T.dump() + " is not a positive time");
    d.flight_time_s = T.get<double>();
    for (const Json& n : Field(j, "keyframe_names", result_file))
      d.keyframe_names.push_back(n.is_string() ? n.get<std::string>() : n.dump());
    d.keyframe_times_s = Numbers(j, "keyframe_times_s", result_file);
    d.keyframe_times_initial_s = Numbers(j, "keyframe_times_initial_s", result_file);
    if (d.keyframe_times_s.size() != d.keyframe_names.size() ||
        d.keyframe_times_initial_s.size() != d.keyframe_names.size())
      throw InputError(result_file,
                       "keyframe_times_s",
                       std::to_string(d.keyframe_times_s.size()) + " times for " +
                           std::to_string(d.keyframe_names.size()) + " keyframes");
  }

  const capture::Storage table = capture::ReadStorage(mot_path);
  const Eigen::Index n = table.time_s.size();
  if (n < 2) throw InputError(mot_file, "rows", std::to_string(n) + " samples: not a motion");
  if (std::abs(table.time_s(0)) > 1e-6)
    throw InputError(mot_file,
                     "time",
                     "starts at " + std::to_string(table.time_s(0)) + " s, not at the take-off");
  for (Eigen::Index k = 1; k < n; ++k)
    if (!(table.time_s(k) > table.time_s(k - 1)))
      throw InputError(mot_file, "time", "does not increase at row " + std::to_string(k + 1));

  const std::vector<std::string> names = MakeCoordinateNames(model);
  const auto column = [&](const std::string& label) {
    const int c = table.FindColumn(label);
    if (c < 0)
      throw InputError(mot_file,
                       label,
                       "no such column: the design was not made for a standard human like this "
                       "athlete's");
    return c;
  };
  const double angle = table.in_degrees ? kDegToRad : 1.0;
  const int tx = column("pelvis_tx"), ty = column("pelvis_ty"), tz = column("pelvis_tz");
  const int cs = column("somersault"), ct = column("tilt"), cw = column("twist");
  std::set<std::string> used = {
      "pelvis_tx", "pelvis_ty", "pelvis_tz", "somersault", "tilt", "twist"};
  std::vector<int> joint_columns;
  for (size_t i = dynamics::kRootNq; i < names.size(); ++i) {
    joint_columns.push_back(column(names[i]));
    used.insert(names[i]);
  }
  for (const std::string& label : table.labels)
    if (!used.count(label))
      throw InputError(mot_file, label, "a column this athlete's standard human does not have");

  Motion& m = d.motion;
  m.coordinate_names = names;
  m.time_s = table.time_s;
  m.q.resize(model.nq(), n);
  m.rate_hz = (n - 1) / (table.time_s(n - 1) - table.time_s(0));
  for (Eigen::Index k = 0; k < n; ++k) {
    const auto value = [&](int c) {
      const double x = table.data(k, c);
      if (!std::isfinite(x))
        throw InputError(
            mot_file, table.labels[size_t(c)], "row " + std::to_string(k + 1) + " is not a number");
      return x;
    };
    Eigen::VectorXd q(model.nq());
    q.head<3>() = Eigen::Vector3d(value(tx), value(ty), value(tz));
    const Eigen::Quaterniond q_WB(Eigen::AngleAxisd(value(cs) * angle, Eigen::Vector3d::UnitY()) *
                                  Eigen::AngleAxisd(value(ct) * angle, Eigen::Vector3d::UnitX()) *
                                  Eigen::AngleAxisd(value(cw) * angle, Eigen::Vector3d::UnitZ()));
    dynamics::SetRootQuaternion<double>(q_WB, q);
    for (size_t i = 0; i < joint_columns.size(); ++i)
      q(dynamics::kRootNq + Eigen::Index(i)) = value(joint_columns[i]) * angle;
    m.q.col(k) = q;
  }
  m.fit.assign(size_t(n), FrameFit{});
  return d;
}

int FrameNearestTime(const Motion& motion, double t_s) {
  const Eigen::VectorXd& t = motion.time_s;
  if (t.size() == 0) return 0;
  const double* begin = t.data();
  const double* end = t.data() + t.size();
  const double* it = std::lower_bound(begin, end, t_s);
  if (it == end) return int(t.size()) - 1;
  if (it != begin && (t_s - *(it - 1)) < (*it - t_s)) --it;
  return int(it - begin);
}

SkillGhost MakeSkillGhost(const SkillDesign& design,
                                const SkillOptimizationResult& result,
                                double rate_hz) {
  SkillGhost d;
  d.name = design.skill().name;
  d.fig_code = design.skill().fig_code;
  d.athlete = design.skill().athlete.name;
  d.flight_time_s = design.flight_time_s();
  for (const SkillKeyframe& k : design.skill().keyframes) d.keyframe_names.push_back(k.name);
  const auto to_std = [](const Eigen::VectorXd& v) {
    return std::vector<double>(v.begin(), v.end());
  };
  d.keyframe_times_s = to_std(result.optimized.times_s);
  d.keyframe_times_initial_s = to_std(result.times_initial_s);
  d.motion = SampleSkillMotion(design, result.optimized, rate_hz);
  return d;
}

}  // namespace acro::analysis
