#pragma once

// The library's one way to parse JSON it did not write itself in this process (an analysis
// directory's provenance.json and jumps.json, an optimisation's result.json): every nlohmann
// exception — a syntax error, a number beyond double — becomes acro::InputError naming the source.

#include <string>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "acro/base/input_error.h"

namespace acro::library::internal {

inline nlohmann::json ParseJsonText(const std::string& text, const std::string& source) {
  try {
    return nlohmann::json::parse(text);
  } catch (const nlohmann::json::parse_error& e) {
    throw InputError(source, AtByte(static_cast<long long>(e.byte)), "not JSON");
  } catch (const nlohmann::json::exception& e) {
    throw InputError(source, "", fmt::format("not JSON: {}", e.what()));
  }
}

}  // namespace acro::library::internal
