// FIG numeric codes and difficulty against the worked examples of the 2025–2028 Code of Points
// (as listed in the issue) and the rules they illustrate.
#include "acro/fig/skill.h"

#include <gtest/gtest.h>

#include "acro/base/input_error.h"

namespace acro::fig {
namespace {

using Dir = SomersaultDirection;

struct Example {
  const char* name;
  const char* code;
  Dir direction;
  int tenths;
};

TEST(FigDifficulty, CodeOfPointsWorkedExamples) {
  const Example examples[] = {
      {"back somersault tuck", "40o", Dir::kBackward, 5},
      {"back somersault pike", "40<", Dir::kBackward, 6},
      {"barani", "41/", Dir::kForward, 6},
      {"rudolph straight", "43/", Dir::kForward, 8},
      {"double full straight", "44/", Dir::kBackward, 9},
      {"cody tuck", "500o", Dir::kBackward, 6},
      {"double back tuck", "800o", Dir::kBackward, 11},
      {"double back pike", "800<", Dir::kBackward, 13},
      {"full-in full-out tuck", "822o", Dir::kBackward, 15},
      {"full-in full-out straight", "822/", Dir::kBackward, 17},
      {"full randy tuck", "825o", Dir::kForward, 20},
      {"full randy pike", "825<", Dir::kForward, 22},
      {"triple back tuck", "12000o", Dir::kBackward, 18},
      {"triple back pike", "12000<", Dir::kBackward, 21},
      {"full-full-full tuck", "12222o", Dir::kBackward, 32},
      {"full-full-full straight", "12222/", Dir::kBackward, 35},
      {"half-in rudy-out quadriffis tuck", "161003o", Dir::kBackward, 37},
      {"half-in rudy-out quadriffis pike", "161003<", Dir::kBackward, 41},
  };
  for (const Example& e : examples) {
    SCOPED_TRACE(e.name);
    const FigSkill skill = ParseFigCode(e.code, e.direction);
    const FigDifficulty d = CalcFigDifficulty(skill);
    EXPECT_EQ(d.total_tenths(), e.tenths) << d.Explain();
    EXPECT_EQ(FormatFigCode(skill), e.code);
  }
}

TEST(FigDifficulty, DirectionFromTwistParityMatchesTheNamedSkills) {
  // Without an explicit direction, odd total half twists mean a forward take-off.
  EXPECT_EQ(ParseFigCode("41/").direction, Dir::kForward);
  EXPECT_EQ(ParseFigCode("825o").direction, Dir::kForward);
  EXPECT_EQ(ParseFigCode("822o").direction, Dir::kBackward);
  EXPECT_EQ(ParseFigCode("00").direction, Dir::kNone);
  EXPECT_EQ(FigSkillName(ParseFigCode("41/")), "barani");
  EXPECT_EQ(FigSkillName(ParseFigCode("822o")), "full-in full-out");
  EXPECT_EQ(FigSkillName(ParseFigCode("00")), "straight jump");
}

TEST(FigDifficulty, RulesHoldBeyondTheExamples) {
  // A forward double gets no backward bonus; a triple front equals the triple's table value.
  EXPECT_EQ(CalcFigDifficulty(ParseFigCode("800o", Dir::kForward)).total_tenths(), 10);
  EXPECT_EQ(CalcFigDifficulty(ParseFigCode("12000o", Dir::kForward)).total_tenths(), 16);
  // ¾ somersault: 0.1 per quarter, no completion value; straight jump: nothing.
  EXPECT_EQ(CalcFigDifficulty(ParseFigCode("30<", Dir::kForward)).total_tenths(), 3);
  EXPECT_EQ(CalcFigDifficulty(ParseFigCode("00")).total_tenths(), 0);
  EXPECT_EQ(CalcFigDifficulty(ParseFigCode("02")).total_tenths(), 2);
  // Shape bonus: a single with twist gets none; a double with twist gets it per somersault.
  EXPECT_EQ(CalcFigDifficulty(ParseFigCode("42/")).shape_bonus_tenths, 0);
  EXPECT_EQ(CalcFigDifficulty(ParseFigCode("822/")).shape_bonus_tenths, 2);
  // Doubles: the twisting bonus starts beyond 720° of twist (4 half twists).
  EXPECT_EQ(CalcFigDifficulty(ParseFigCode("822o")).twisting_bonus_tenths, 0);
  EXPECT_EQ(CalcFigDifficulty(ParseFigCode("823o")).twisting_bonus_tenths, 1);
  EXPECT_EQ(CalcFigDifficulty(ParseFigCode("800o")).Explain(),
            "1.0 somersault + 0.1 backward multiple = 1.1");
}

TEST(FigCode, MalformedCodesNameTheCode) {
  for (const char* bad : {"", "4", "40x", "40", "8000o", "4o0", "1o"}) {
    try {
      ParseFigCode(bad);
      ADD_FAILURE() << "accepted '" << bad << "'";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(std::string("'") + bad + "'"), std::string::npos)
          << e.what();
    }
  }
}

}  // namespace
}  // namespace acro::fig
