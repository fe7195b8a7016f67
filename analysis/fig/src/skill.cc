#include "acro/fig/skill.h"

#include <cctype>
#include <numeric>
#include <sstream>

#include "acro/base/input_error.h"

namespace acro::fig {
namespace {

char ShapeChar(SkillShape shape) {
  switch (shape) {
    case SkillShape::kTuck:
      return 'o';
    case SkillShape::kPike:
      return '<';
    case SkillShape::kStraight:
      return '/';
  }
  return '/';
}

std::string Tenths(int tenths) {
  std::ostringstream out;
  out << tenths / 10 << '.' << tenths % 10;
  return out.str();
}

}  // namespace

int FigSkill::total_half_twists() const {
  return std::accumulate(half_twists.begin(), half_twists.end(), 0);
}

int FigSkill::SomersaultSlots(int quarter_somersaults) {
  return quarter_somersaults <= 0 ? 1 : (quarter_somersaults + 3) / 4;
}

std::string FormatFigCode(const FigSkill& skill) {
  std::string code = std::to_string(skill.quarter_somersaults);
  for (int h : skill.half_twists) code += std::to_string(h);
  if (skill.quarter_somersaults > 0 || skill.shape != SkillShape::kStraight)
    code += ShapeChar(skill.shape);
  return code;
}

FigSkill ParseFigCode(std::string_view code, SomersaultDirection direction) {
  const std::string text(code);
  auto fail = [&](const std::string& why) -> FigSkill {
    throw InputError("", "FIG code '" + text + "'", why);
  };
  std::string digits;
  FigSkill skill;
  std::size_t i = 0;
  while (i < code.size() && std::isdigit(static_cast<unsigned char>(code[i]))) digits += code[i++];
  if (digits.size() < 2)
    return fail("expected quarter somersaults then one twist digit per somersault");
  if (i + 1 < code.size()) return fail("unexpected characters after the shape");
  if (i < code.size()) {
    switch (code[i]) {
      case 'o':
        skill.shape = SkillShape::kTuck;
        break;
      case '<':
        skill.shape = SkillShape::kPike;
        break;
      case '/':
        skill.shape = SkillShape::kStraight;
        break;
      default:
        return fail(std::string("unknown shape '") + code[i] + "' (o tuck, < pike, / straight)");
    }
  }
  // The quarter count has one or two digits: the one whose twist digits fill the rest exactly.
  bool found = false;
  for (std::size_t width = 1; width <= 2 && width < digits.size(); ++width) {
    const int quarters = std::stoi(digits.substr(0, width));
    if (width == 2 && digits[0] == '0') continue;
    if (static_cast<int>(digits.size() - width) == FigSkill::SomersaultSlots(quarters)) {
      skill.quarter_somersaults = quarters;
      for (std::size_t k = width; k < digits.size(); ++k)
        skill.half_twists.push_back(digits[k] - '0');
      found = true;
      break;
    }
  }
  if (!found) return fail("the number of twist digits does not match the quarter somersaults");
  if (skill.quarter_somersaults > 0 && i == code.size())
    return fail("a somersault needs a shape (o, <, /)");
  if (skill.quarter_somersaults == 0) {
    skill.direction = SomersaultDirection::kNone;
  } else if (direction != SomersaultDirection::kNone) {
    skill.direction = direction;
  } else {
    skill.direction = skill.total_half_twists() % 2 ? SomersaultDirection::kForward
                                                    : SomersaultDirection::kBackward;
  }
  return skill;
}

int FigDifficulty::total_tenths() const {
  return somersault_tenths + twist_tenths + shape_bonus_tenths + backward_bonus_tenths +
         twisting_bonus_tenths;
}

std::string FigDifficulty::Explain() const {
  std::string out = Tenths(somersault_tenths) + " somersault";
  auto add = [&](int tenths, const char* what) {
    if (tenths != 0) out += " + " + Tenths(tenths) + " " + what;
  };
  add(twist_tenths, "twist");
  add(shape_bonus_tenths, "shape");
  add(backward_bonus_tenths, "backward multiple");
  add(twisting_bonus_tenths, "twisting multiple");
  return out + " = " + Tenths(total_tenths());
}

FigDifficulty CalcFigDifficulty(const FigSkill& skill) {
  FigDifficulty d;
  const int q = skill.quarter_somersaults;
  const int complete = q / 4;
  const int half_twists = skill.total_half_twists();
  // Somersault rotation: 0.1 per quarter, complete somersaults at their table value.
  static constexpr int kCompleteTenths[] = {0, 5, 10, 16, 22};
  d.somersault_tenths =
      (complete <= 4 ? kCompleteTenths[complete] : 22 + 6 * (complete - 4)) + (q % 4);
  d.twist_tenths = half_twists;
  const bool pike_or_straight = q > 0 && skill.shape != SkillShape::kTuck;
  if (pike_or_straight && q >= 4 && q <= 7 && half_twists == 0) d.shape_bonus_tenths = 1;
  if (pike_or_straight && q >= 8) d.shape_bonus_tenths = complete;
  if (skill.direction == SomersaultDirection::kBackward && complete >= 2)
    d.backward_bonus_tenths = complete - 1;
  if (complete == 2) d.twisting_bonus_tenths = std::max(0, half_twists - 4);
  if (complete == 3) d.twisting_bonus_tenths = 2 * std::max(0, half_twists - 2);
  if (complete >= 4) d.twisting_bonus_tenths = 2 * half_twists;
  return d;
}

std::string FigSkillName(const FigSkill& skill) {
  const int q = skill.quarter_somersaults;
  const std::vector<int>& h = skill.half_twists;
  const bool back = skill.direction == SomersaultDirection::kBackward;
  if (q == 0) {
    static const char* kJumps[] = {"straight jump", "half twist jump", "full twist jump"};
    return h.size() == 1 && h[0] <= 2 ? kJumps[h[0]] : "";
  }
  if (q == 4 && h.size() == 1) {
    static const char* kSingles[] = {
        "", "barani", "full", "rudolph", "double full", "randolph", "triple full", "adolph"};
    if (h[0] == 0) return back ? "back somersault" : "front somersault";
    return h[0] < 8 ? kSingles[h[0]] : "";
  }
  if (q == 5 && h == std::vector<int>{0, 0}) return back ? "cody" : "ball out";
  if (q == 8 && h.size() == 2) {
    if (h[0] == 0 && h[1] == 0) return back ? "double back" : "double front";
    if (h[0] == 0 && h[1] == 1) return "barani out";
    if (h[0] == 0 && h[1] == 3) return "rudy out";
    if (h[0] == 1 && h[1] == 1) return "half-in half-out";
    if (h[0] == 2 && h[1] == 2) return "full-in full-out";
    if (h[0] == 2 && h[1] == 0) return "full-in back out";
    if (h[0] == 0 && h[1] == 2) return "full-out";
    if (h[0] == 2 && h[1] == 5) return "full randy";
    if (h[0] == 2 && h[1] == 1) return "full-in half-out";
  }
  if (q == 12 && h.size() == 3) {
    if (h == std::vector<int>{0, 0, 0}) return back ? "triple back" : "triple front";
    if (h == std::vector<int>{2, 2, 2}) return "full-full-full";
    if (h == std::vector<int>{1, 0, 1}) return "half-in half-out triffis";
  }
  if (q == 16 && h == std::vector<int>{1, 0, 0, 3}) return "half-in rudy-out quadriffis";
  return "";
}

}  // namespace acro::fig
