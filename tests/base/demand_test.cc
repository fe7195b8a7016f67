#include "acro/base/demand.h"

#include <gtest/gtest.h>

#include "acro/base/input_error.h"

namespace acro {
namespace {

TEST(Demand, ThrowsWithConditionAndPlace) {
  try {
    ACRO_DEMAND(1 + 1 == 3);
    FAIL() << "ACRO_DEMAND did not throw";
  } catch (const std::logic_error& e) {
    EXPECT_NE(std::string(e.what()).find("1 + 1 == 3"), std::string::npos);
    EXPECT_NE(std::string(e.what()).find("demand_test.cc"), std::string::npos);
  }
  EXPECT_NO_THROW(ACRO_DEMAND(2 > 1));
}

TEST(InputError, IsOneLineNamingFileWhereAndWhat) {
  InputError e("trial.c3d", AtByte(512), "parameter name\nlength -3");
  EXPECT_STREQ(e.what(), "trial.c3d: byte 512: parameter name\\nlength -3");
}

}  // namespace
}  // namespace acro
