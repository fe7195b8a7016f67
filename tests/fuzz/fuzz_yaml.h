#pragma once

// The YAML readers' fuzz entry point: the bytes parsed as Acrolab YAML, then read as each of the
// files written in it — athlete profile, Yeadon measurements, skill, routine, marker set. Each read
// accepts the tree or rejects it with acro::InputError; anything else is a bug. Used by the
// libFuzzer target (yaml_fuzz.cc) and by the corpus replay in the suite
// (tests/analysis/design/yaml_corpus_test.cc).

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include "acro/athlete/athlete_profile.h"
#include "acro/athlete/yeadon_measurements.h"
#include "acro/base/input_error.h"
#include "acro/base/yaml.h"
#include "acro/design/routine_design.h"
#include "acro/design/skill_file.h"
#include "acro/reconstruct/markerset.h"
#include "fuzz_accepts.h"

namespace acro::fuzz {

/// Number of readers that accepted the input (0–6, the parse counting as one). Relative paths in
/// the input (a skill's athlete) are taken from `base_dir`; the rejections' messages go to
/// `errors`.
inline int FeedYamlReaders(const std::uint8_t* data,
                           std::size_t size,
                           const std::filesystem::path& base_dir,
                           std::vector<std::string>* errors = nullptr) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  YamlNode root;
  try {
    root = ParseYaml(text, "fuzz.yaml");
  } catch (const InputError& e) {
    if (errors) errors->push_back(e.what());
    return 0;
  }
  return 1 + Accepts(errors, [&] { analysis::AthleteProfileFromYaml(root, base_dir); }) +
         Accepts(errors, [&] { analysis::YeadonMeasurementsFromYaml(root); }) +
         Accepts(errors, [&] { analysis::SkillFromYaml(root, base_dir); }) +
         Accepts(errors, [&] { analysis::RoutineSpecFromYaml(root, base_dir); }) +
         Accepts(errors, [&] { analysis::MarkerSetFromYaml(root); });
}

}  // namespace acro::fuzz
