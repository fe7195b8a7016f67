#pragma once

// The soak-type tests' full versions (a season of 600 routines, 1 000 random seeks into the
// reference videos, …) run with ACRO_LONG_TESTS=1; the default run keeps each test's checks on a
// smaller amount of the same kind of work (docs/testing.md).

#include <cstdlib>
#include <string>

namespace acro::testing {

inline bool LongTests() {
  const char* v = std::getenv("ACRO_LONG_TESTS");
  return v != nullptr && *v != '\0' && std::string(v) != "0";
}

}  // namespace acro::testing
