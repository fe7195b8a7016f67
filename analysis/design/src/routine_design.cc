#include "acro/design/routine_design.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <exception>
#include <map>
#include <mutex>
#include <thread>
#include <utility>

#include <fmt/format.h>

#include "acro/base/input_error.h"
#include "acro/base/yaml.h"

namespace acro::analysis {
namespace {

constexpr double kPi = 3.14159265358979323846;

// The skill's place for messages: "skill 3 (42/)".
std::string Where(const RoutineSkillSpec& s, size_t index) {
  return (s.where.empty() ? fmt::format("skill {}", index + 1) : s.where) + " (" + s.code + ")";
}

// Designs every skill of the spec at its flight time, `threads` at once; the first failure in
// routine order is thrown naming its skill.
std::vector<SkillFromCodeResult> DesignSkills(const RoutineSpec& spec,
                                              const std::vector<double>& flight_times,
                                              const RoutineDesignOptions& options) {
  const size_t n = spec.skills.size();
  std::vector<SkillFromCodeResult> designs(n);
  std::vector<std::exception_ptr> errors(n);
  std::atomic<size_t> next{0};
  std::mutex say;
  auto work = [&] {
    for (size_t i = next++; i < n; i = next++) {
      try {
        SkillFromCodeOptions o = options.skill;
        o.flight_time_s = flight_times[i];
        o.takeoff_vertical_velocity_mps = 0.0;
        o.progress = nullptr;
        designs[i] = DesignSkillFromCode(spec.skills[i].code, spec.athlete_path, o);
        if (options.progress) {
          const std::lock_guard<std::mutex> lock(say);
          options.progress(fmt::format("designed {}: {:.3f} s of flight, {} keyframes",
                                       Where(spec.skills[i], i),
                                       designs[i].flight_time_s,
                                       designs[i].skill.keyframes.size()));
        }
      } catch (...) {
        errors[i] = std::current_exception();
      }
    }
  };
  const int hw = static_cast<int>(std::thread::hardware_concurrency());
  const int threads =
      std::clamp(options.threads > 0 ? options.threads : std::max(hw, 1), 1, static_cast<int>(n));
  std::vector<std::thread> pool;
  for (int t = 1; t < threads; ++t) pool.emplace_back(work);
  work();
  for (std::thread& t : pool) t.join();
  for (size_t i = 0; i < n; ++i) {
    if (!errors[i]) continue;
    try {
      std::rethrow_exception(errors[i]);
    } catch (const InputError& e) {
      throw InputError("", Where(spec.skills[i], i), e.what());
    }
  }
  return designs;
}

// The routine's plan of one designed skill: its flight, rotation and joints' schedule, the take-off
// momentum as the design found it, landing at the bed's centre.
RoutineSkillPlan PlanOf(const SkillFromCodeResult& d) {
  RoutineSkillPlan p;
  p.name = d.skill.name;
  p.fig_code = d.skill.fig_code;
  p.flight_s = d.flight_time_s;
  const fig::FigSkill& c = d.code;
  p.direction = c.direction == fig::SomersaultDirection::kForward    ? 1
                : c.direction == fig::SomersaultDirection::kBackward ? -1
                                                                     : 0;
  p.nominal_rad = 2 * kPi * (c.quarter_somersaults / 4);
  // The way the design twists (its option: the athlete's left or right, positive to the left).
  p.twist_halves = (d.air_twist_rad < 0 ? -1 : 1) * c.total_half_twists();
  p.takeoff_lean_rad = d.takeoff_lean_rad;
  p.landing_short_rad = d.landing_short_rad;
  p.track = d.track;
  p.momentum_guess = d.momentum_components;
  return p;
}

}  // namespace

RoutineSpec ReadRoutineSpec(const std::filesystem::path& path) {
  return RoutineSpecFromYaml(ReadYamlFile(path), path.parent_path());
}

RoutineSpec RoutineSpecFromYaml(const YamlNode& root, const std::filesystem::path& base_dir) {
  if (!root.IsMap()) root.Fail("a routine file is a map with `athlete` and `skills`");
  root.RequireKnownKeys({"name", "athlete", "skills"});
  RoutineSpec spec;
  if (const YamlNode* name = root.Find("name")) spec.name = name->AsString();
  spec.athlete_path = root.At("athlete").AsString();
  if (spec.athlete_path.is_relative()) spec.athlete_path = base_dir / spec.athlete_path;
  const std::string file_name = std::filesystem::path(root.file()).filename().string();
  const YamlNode& skills = root.At("skills");
  if (!skills.IsSequence() || skills.items().empty())
    skills.Fail("expected a list of skills (FIG codes, or maps with `code`)");
  if (skills.items().size() > 100) skills.Fail("more than 100 skills");
  for (const YamlNode& item : skills.items()) {
    RoutineSkillSpec s;
    s.where = file_name + ": " + item.Where();
    if (item.IsMap()) {
      item.RequireKnownKeys({"code", "flight_time_s"});
      s.code = item.At("code").AsString();
      if (const YamlNode* t = item.Find("flight_time_s")) {
        s.flight_time_s = t->AsDouble();
        if (!(s.flight_time_s >= 0.5 && s.flight_time_s <= 3.0))
          t->Fail(fmt::format("{} s is outside 0.5–3 s", s.flight_time_s));
      }
    } else {
      s.code = item.AsString();
    }
    spec.skills.push_back(std::move(s));
  }
  return spec;
}

RoutineSpec RoutineSpecFromCodes(const std::string& codes,
                                 const std::filesystem::path& athlete_path) {
  RoutineSpec spec;
  spec.athlete_path = athlete_path;
  std::string code;
  auto flush = [&] {
    if (code.empty()) return;
    spec.skills.push_back({code, 0.0, fmt::format("skill {}", spec.skills.size() + 1)});
    code.clear();
  };
  for (char ch : codes) {
    if (ch == ' ' || ch == ',' || ch == '\t' || ch == '\n') {
      flush();
    } else {
      code += ch;
    }
  }
  flush();
  if (spec.skills.empty()) throw InputError("", "--codes", "no FIG code given");
  if (spec.skills.size() > 100) throw InputError("", "--codes", "more than 100 skills");
  return spec;
}

std::vector<double> ChooseFlightTimes(const std::vector<double>& needed, double max_change) {
  std::vector<double> T = needed;
  for (size_t i = T.size(); i-- > 1;) T[i - 1] = std::max(T[i - 1], T[i] - max_change);
  return T;
}

RoutineDesignResult DesignRoutine(const RoutineSpec& spec, const RoutineDesignOptions& options) {
  if (spec.skills.empty()) throw InputError("", "routine", "no skill");
  RoutineDesignResult result;
  result.spec = spec;

  // The composition: every code readable, no skill repeated (FIG Code of Points, trampoline: a
  // repeated element does not count; we refuse it), the skill count.
  std::map<std::string, size_t> seen;
  std::vector<double> needed;
  for (size_t i = 0; i < spec.skills.size(); ++i) {
    const RoutineSkillSpec& s = spec.skills[i];
    fig::FigSkill code;
    try {
      code = fig::ParseFigCode(s.code);
    } catch (const InputError& e) {
      throw InputError("", Where(s, i), e.what());
    }
    const std::string canonical = fig::FormatFigCode(code);
    const auto [it, inserted] = seen.emplace(canonical, i);
    if (!inserted)
      throw InputError("",
                       Where(s, i),
                       fmt::format("repeats skill {} ({}): a routine holds every skill once",
                                   it->second + 1,
                                   spec.skills[it->second].code));
    needed.push_back(s.flight_time_s > 0 ? s.flight_time_s : DefaultFlightTime(code));
  }
  if (options.fig_skill_count > 0 && int(spec.skills.size()) != options.fig_skill_count)
    result.notes.push_back(fmt::format(
        "{} skills: a FIG routine has {}", spec.skills.size(), options.fig_skill_count));

  // The flights, each skill designed at its own, and whether the athlete can do it.
  const std::vector<double> T = ChooseFlightTimes(needed, options.max_flight_time_change_s);
  for (size_t i = 0; i < T.size(); ++i)
    if (T[i] > needed[i] + 1e-9 && options.progress)
      options.progress(fmt::format("{}: flight raised from {:.2f} s to {:.2f} s for the next skill",
                                   Where(spec.skills[i], i),
                                   needed[i],
                                   T[i]));
  result.skills = DesignSkills(spec, T, options);
  for (size_t i = 0; i < result.skills.size(); ++i) {
    const SkillFromCodeResult& d = result.skills[i];
    if (!d.feasible())
      throw InputError("", Where(spec.skills[i], i), "not feasible: " + d.not_feasible.front());
    result.difficulty += d.difficulty.total();
  }

  // The routine through the bed.
  if (options.progress) options.progress("flying the routine through the bed contacts");
  std::vector<RoutineSkillPlan> plans;
  for (const SkillFromCodeResult& d : result.skills) plans.push_back(PlanOf(d));
  // (the athlete as the designs read it)
  result.simulation =
      SimulateRoutine(result.skills.front().skill.athlete, plans, options.simulation);
  const SimulatedRoutine& sim = result.simulation;
  for (size_t i = 0; i < sim.flights.size(); ++i) {
    const RoutineFlightTruth& f = sim.flights[i];
    result.time_of_flight_s += f.landing_s - f.takeoff_s;
    // The contact before flight i gives its take-off.
    const RoutineContactTruth& c = sim.contacts[i];
    if (i > 0 && std::abs(c.push_rad) > options.max_push_rad)
      throw InputError(
          "",
          Where(spec.skills[i], i),
          fmt::format("the contact after skill {} ({}) would need a push of {:.0f}° of hip flexion "
                      "to reach its {:.2f} s of flight, more than {:.0f}°",
                      i,
                      spec.skills[i - 1].code,
                      c.push_rad * 180 / kPi,
                      result.skills[i].flight_time_s,
                      options.max_push_rad * 180 / kPi));
    if (i > 0 && std::abs(c.takeoff_velocity_error_m_per_s) > 1e-3)
      throw InputError("",
                       Where(spec.skills[i], i),
                       fmt::format("the contact after skill {} finds no push that gives its "
                                   "take-off (missed by {:.3f} m/s)",
                                   i,
                                   c.takeoff_velocity_error_m_per_s));
  }
  return result;
}

std::vector<fig::PerformedFlight> DesignedFlights(const RoutineDesignResult& result) {
  std::vector<fig::PerformedFlight> flights;
  for (size_t i = 0; i < result.skills.size(); ++i) {
    fig::PerformedFlight f;
    f.skill = result.skills[i].code;
    f.time_of_flight_s =
        i < result.simulation.flights.size()
            ? result.simulation.flights[i].landing_s - result.simulation.flights[i].takeoff_s
            : result.skills[i].flight_time_s;
    flights.push_back(std::move(f));
  }
  return flights;
}

}  // namespace acro::analysis
