#pragma once

// The one-line message of the acro::InputError a call throws, for tests of bad input.

#include <functional>
#include <string>

#include "acro/base/input_error.h"

namespace acro::testing {

/// What `f` throws as acro::InputError, or "" when it throws nothing.
inline std::string InputErrorOf(const std::function<void()>& f) {
  try {
    f();
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

}  // namespace acro::testing
