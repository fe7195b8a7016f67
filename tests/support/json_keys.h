#pragma once

// The keys of a parsed JSON object, for the tests that check what a JSON writer produced.

#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace acro::testing {

/// The keys of `object` in the order the text has them (parse it as nlohmann::ordered_json).
inline std::vector<std::string> JsonKeys(const nlohmann::ordered_json& object) {
  std::vector<std::string> keys;
  for (const auto& item : object.items()) keys.push_back(item.key());
  return keys;
}

}  // namespace acro::testing
