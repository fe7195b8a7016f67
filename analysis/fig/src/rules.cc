#include "acro/fig/rules.h"

#include <cmath>

#include <fmt/format.h>

#include "acro/base/input_error.h"
#include "acro/base/yaml.h"

namespace acro::fig {
namespace {

BodyPosition ReadPosition(const YamlNode& node) {
  const std::string s = node.AsString();
  if (s == "feet") return BodyPosition::kFeet;
  if (s == "front") return BodyPosition::kFront;
  if (s == "back") return BodyPosition::kBack;
  node.Fail(fmt::format("'{}' is not a position (feet, front or back)", s));
}

std::vector<BodyPosition> ReadPositions(const YamlNode& node) {
  std::vector<BodyPosition> out;
  if (node.IsScalar()) {
    out.push_back(ReadPosition(node));
  } else if (node.IsSequence()) {
    for (const YamlNode& item : node.items()) out.push_back(ReadPosition(item));
  } else {
    node.Fail("a position or a list of positions (feet, front, back)");
  }
  return out;
}

int ReadCount(const YamlNode& node, int lo, int hi) {
  const int v = node.AsInt();
  if (v < lo || v > hi) node.Fail(fmt::format("{} is outside {}..{}", v, lo, hi));
  return v;
}

double ReadNumber(const YamlNode& node, double lo, double hi) {
  const double v = node.AsDouble();
  if (!std::isfinite(v) || v < lo || v > hi)
    node.Fail(fmt::format("{} is outside {}..{}", v, lo, hi));
  return v;
}

// A pair [from, to] in metres for a zone's extent.
void ReadRange(const YamlNode& node, double* lo, double* hi) {
  const std::vector<double> v = node.AsDoubleList();
  if (v.size() != 2)
    node.Fail(fmt::format("a range is two numbers [from, to] in metres, got {}", v.size()));
  for (double x : v)
    if (!std::isfinite(x) || std::abs(x) > 10.0) node.Fail(fmt::format("{} m is outside ±10 m", x));
  if (v[0] >= v[1]) node.Fail(fmt::format("[{}, {}] is empty", v[0], v[1]));
  *lo = v[0];
  *hi = v[1];
}

ElementRequirement ReadRequirement(const YamlNode& node) {
  if (!node.IsMap()) node.Fail("a requirement is a map (name, min_somersault_quarters, …)");
  node.RequireKnownKeys(
      {"name", "min_somersault_quarters", "min_half_twists", "landing", "takeoff", "direction"});
  ElementRequirement r;
  r.name = node.At("name").AsString();
  if (r.name.empty() || r.name.size() > 200)
    node.At("name").Fail("a requirement's name is 1 to 200 characters");
  if (const YamlNode* n = node.Find("min_somersault_quarters"))
    r.min_quarter_somersaults = ReadCount(*n, 0, 20);
  if (const YamlNode* n = node.Find("min_half_twists")) r.min_half_twists = ReadCount(*n, 0, 20);
  if (const YamlNode* n = node.Find("landing")) r.landing = ReadPositions(*n);
  if (const YamlNode* n = node.Find("takeoff")) r.takeoff = ReadPositions(*n);
  if (const YamlNode* n = node.Find("direction")) {
    const std::string d = n->AsString();
    if (d == "forward")
      r.direction = SomersaultDirection::kForward;
    else if (d == "backward")
      r.direction = SomersaultDirection::kBackward;
    else if (d != "any")
      n->Fail(fmt::format("'{}' is not a direction (forward, backward or any)", d));
  }
  return r;
}

HdZones ReadZones(const YamlNode& node) {
  node.RequireKnownKeys({"zones", "outside", "source"});
  HdZones z;
  z.zones.clear();
  z.source = node.At("source").AsString();
  const YamlNode& zones = node.At("zones");
  if (!zones.IsSequence() || zones.items().empty() || zones.items().size() > 100)
    zones.Fail("a list of 1 to 100 zones");
  for (const YamlNode& item : zones.items()) {
    if (!item.IsMap()) item.Fail("a zone is a map (name, x_m, y_m, deduction)");
    item.RequireKnownKeys({"name", "x_m", "y_m", "deduction"});
    HdZone r;
    r.name = item.At("name").AsString();
    ReadRange(item.At("x_m"), &r.x_min, &r.x_max);
    ReadRange(item.At("y_m"), &r.y_min, &r.y_max);
    r.deduction = ReadNumber(item.At("deduction"), 0.0, 1.0);
    z.zones.push_back(r);
  }
  const YamlNode& outside = node.At("outside");
  if (!outside.IsMap()) outside.Fail("a map (name, deduction)");
  outside.RequireKnownKeys({"name", "deduction"});
  z.outside_name = outside.At("name").AsString();
  z.outside_deduction = ReadNumber(outside.At("deduction"), 0.0, 1.0);
  return z;
}

}  // namespace

double FaultRule::DeductionFor(double value) const {
  double d = 0.0;
  for (const auto& [threshold, deduction] : steps)
    if (smaller_is_worse ? value <= threshold : value >= threshold) d = deduction;
  return d;
}

bool FaultRule::Exceeds(double value, double uncertainty) const {
  if (steps.empty() || !std::isfinite(value)) return false;
  const double first = steps.front().first;
  return smaller_is_worse ? value <= first - uncertainty : value >= first + uncertainty;
}

ExecutionRules ExecutionRules::Default() {
  ExecutionRules r;
  r.faults = {
      {"knees_bent", "deg", {{15, 0.1}, {45, 0.2}, {90, 0.3}}, false},
      {"arms_bent", "deg", {{20, 0.1}, {60, 0.2}}, false},
      {"arms_out", "deg", {{30, 0.1}, {60, 0.2}}, false},
      {"legs_apart", "m", {{0.10, 0.1}, {0.30, 0.2}}, false},
      {"body_bent", "deg", {{20, 0.1}, {45, 0.2}}, false},
      {"pike_open", "deg", {{100, 0.1}, {125, 0.2}}, false},
      {"tuck_open", "deg", {{90, 0.1}, {115, 0.2}}, false},
      {"late_opening", "s", {{0.20, 0.1}, {0.10, 0.2}}, true},
      // Measured and shown; no deduction by default: where it lands is H's (a club may add steps).
      {"travel", "m", {}, false},
      {"height_loss", "m", {{0.30, 0.1}, {0.60, 0.2}}, false},
  };
  return r;
}

const FaultRule* ExecutionRules::Find(std::string_view fault) const {
  for (const FaultRule& f : faults)
    if (f.fault == fault) return &f;
  return nullptr;
}

const char* BodyPositionName(BodyPosition position) {
  switch (position) {
    case BodyPosition::kFront:
      return "front";
    case BodyPosition::kBack:
      return "back";
    case BodyPosition::kFeet:
      break;
  }
  return "feet";
}

RoutineRules RoutineRules::FigSenior() {
  RoutineRules r;
  r.name = "FIG senior, individual trampoline";
  r.source =
      "FIG Code of Points 2025-2028, trampoline (ten different elements; all elements' difficulty "
      "counts in both routines since 2022)";
  return r;
}

bool RoutineRules::IsValid(std::string* why) const {
  auto fail = [&](std::string text) {
    if (why != nullptr) *why = std::move(text);
    return false;
  };
  if (elements < 1 || elements > 20) return fail(fmt::format("elements is {} (1 to 20)", elements));
  if (max_difficulty &&
      !(std::isfinite(*max_difficulty) && *max_difficulty >= 0 && *max_difficulty <= 100))
    return fail(fmt::format("max_difficulty is {} (0 to 100)", *max_difficulty));
  if (max_elements_below_270 && (*max_elements_below_270 < 0 || *max_elements_below_270 > elements))
    return fail(
        fmt::format("max_elements_below_270 is {} (0 to {})", *max_elements_below_270, elements));
  if (static_cast<int>(requirements.size()) > elements)
    return fail(fmt::format("{} requirements for {} elements", requirements.size(), elements));
  if (!(std::isfinite(missing_requirement_penalty) && missing_requirement_penalty >= 0 &&
        missing_requirement_penalty <= 10))
    return fail(
        fmt::format("missing_requirement_penalty is {} (0 to 10)", missing_requirement_penalty));
  if (!(time_of_flight_step > 0 && time_of_flight_step <= 1))
    return fail(fmt::format("time_of_flight_step is {} (above 0, at most 1)", time_of_flight_step));
  return zones.IsValid(why) && synchro.IsValid(why);
}

namespace {

RoutineRules RulesFromYaml(const YamlNode& root, const std::string& origin) {
  if (!root.IsMap())
    throw InputError(origin, root.Where(), "a rule file is a map (name, source, routine, …)");
  root.RequireKnownKeys({"name",
                         "source",
                         "routine",
                         "requirements",
                         "missing_requirement_penalty",
                         "time_of_flight",
                         "horizontal_displacement",
                         "execution",
                         "synchronisation"});
  RoutineRules r;
  r.name = root.At("name").AsString();
  r.source = root.At("source").AsString();
  if (r.source.empty()) root.At("source").Fail("say where the rules come from");
  if (const YamlNode* routine = root.Find("routine")) {
    if (!routine->IsMap()) routine->Fail("a map (elements, different_elements, difficulty, …)");
    routine->RequireKnownKeys({"elements",
                               "different_elements",
                               "difficulty",
                               "max_difficulty",
                               "max_elements_below_270"});
    if (const YamlNode* n = routine->Find("elements")) r.elements = ReadCount(*n, 1, 20);
    if (const YamlNode* n = routine->Find("different_elements")) r.different_elements = n->AsBool();
    if (const YamlNode* n = routine->Find("difficulty")) {
      const std::string d = n->AsString();
      if (d == "all")
        r.difficulty = DifficultyCounted::kAll;
      else if (d == "none")
        r.difficulty = DifficultyCounted::kNone;
      else
        n->Fail(fmt::format("'{}' is not a difficulty rule (all or none)", d));
    }
    if (const YamlNode* n = routine->Find("max_difficulty"); n != nullptr && !n->IsNull())
      r.max_difficulty = ReadNumber(*n, 0.0, 100.0);
    if (const YamlNode* n = routine->Find("max_elements_below_270"); n != nullptr && !n->IsNull())
      r.max_elements_below_270 = ReadCount(*n, 0, r.elements);
  }
  if (const YamlNode* reqs = root.Find("requirements")) {
    if (!reqs->IsSequence() && !reqs->IsNull()) reqs->Fail("a list of requirements");
    for (const YamlNode& item : reqs->items()) r.requirements.push_back(ReadRequirement(item));
    if (static_cast<int>(r.requirements.size()) > r.elements)
      reqs->Fail(fmt::format(
          "{} requirements for a routine of {} elements", r.requirements.size(), r.elements));
  }
  if (const YamlNode* n = root.Find("missing_requirement_penalty"))
    r.missing_requirement_penalty = ReadNumber(*n, 0.0, 10.0);
  if (const YamlNode* tof = root.Find("time_of_flight")) {
    if (!tof->IsMap()) tof->Fail("a map (truncate_to)");
    tof->RequireKnownKeys({"truncate_to"});
    if (const YamlNode* n = tof->Find("truncate_to")) {
      r.time_of_flight_step = n->AsDouble();
      if (!(r.time_of_flight_step > 0 && r.time_of_flight_step <= 1))
        n->Fail(fmt::format("{} is not a step above 0 and at most 1", r.time_of_flight_step));
    }
  }
  if (const YamlNode* sy = root.Find("synchronisation")) {
    if (!sy->IsMap()) sy->Fail("a map (element_points, points_lost_per_s, tolerance_s, source)");
    sy->RequireKnownKeys({"element_points", "points_lost_per_s", "tolerance_s", "source"});
    if (const YamlNode* n = sy->Find("element_points"))
      r.synchro.element_points = ReadNumber(*n, 0.001, 10.0);
    if (const YamlNode* n = sy->Find("points_lost_per_s"))
      r.synchro.points_lost_per_s = ReadNumber(*n, 0.0, 1000.0);
    if (const YamlNode* n = sy->Find("tolerance_s"))
      r.synchro.tolerance_s = ReadNumber(*n, 0.0, 1.0);
    r.synchro.source = sy->At("source").AsString();
    if (r.synchro.source.empty()) sy->At("source").Fail("say where the conversion comes from");
  }
  if (const YamlNode* ex = root.Find("execution")) {
    // A fault's steps replace the default's: `knees_bent: [[15, 0.1], [45, 0.2]]`.
    if (!ex->IsMap())
      ex->Fail("a map of faults (knees_bent, legs_apart, …) to [[threshold, deduction], …]");
    for (const auto& [key, steps] : ex->entries()) {
      FaultRule* rule = nullptr;
      for (FaultRule& f : r.execution.faults)
        if (f.fault == key) rule = &f;
      if (rule == nullptr) {
        std::string known;
        for (const FaultRule& f : r.execution.faults)
          known += (known.empty() ? "" : ", ") + f.fault;
        steps.Fail(fmt::format("unknown fault (known: {})", known));
      }
      if (!steps.IsSequence() || steps.items().empty() || steps.items().size() > 10)
        steps.Fail("1 to 10 steps [threshold, deduction]");
      rule->steps.clear();
      for (const YamlNode& step : steps.items()) {
        const std::vector<double> v = step.AsDoubleList();
        if (v.size() != 2 || !std::isfinite(v[0]) || std::abs(v[0]) > 1000 ||
            !(v[1] >= 0 && v[1] <= 0.5))
          step.Fail(
              "a step is [threshold, deduction] with a finite threshold and a deduction of 0 to "
              "0.5");
        if (!rule->steps.empty() && (rule->smaller_is_worse ? v[0] >= rule->steps.back().first
                                                            : v[0] <= rule->steps.back().first))
          step.Fail(fmt::format("thresholds must {} from step to step",
                                rule->smaller_is_worse ? "fall" : "rise"));
        rule->steps.emplace_back(v[0], v[1]);
      }
    }
  }
  if (const YamlNode* hd = root.Find("horizontal_displacement")) {
    if (!hd->IsMap()) hd->Fail("a map (zones, outside, source)");
    r.zones = ReadZones(*hd);
  }
  std::string why;
  if (!r.IsValid(&why)) throw InputError(origin, root.Where(), why);
  return r;
}

}  // namespace

RoutineRules ParseRules(std::string_view text, const std::string& origin) {
  return RulesFromYaml(ParseYaml(text, origin), origin);
}

RoutineRules LoadRules(const std::filesystem::path& path) {
  return RulesFromYaml(ReadYamlFile(path), path.string());
}

}  // namespace acro::fig
