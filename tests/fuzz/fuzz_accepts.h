#pragma once

// What every fuzz entry point does per reader: run it; it accepts the input (1) or rejects it with
// acro::InputError (0, the message kept in `errors` when given). Anything else escapes: a bug.

#include <string>
#include <vector>

#include "acro/base/input_error.h"

namespace acro::fuzz {

template <class Read>
int Accepts(std::vector<std::string>* errors, Read read) {
  try {
    read();
    return 1;
  } catch (const InputError& e) {
    if (errors) errors->push_back(e.what());
    return 0;
  }
}

}  // namespace acro::fuzz
