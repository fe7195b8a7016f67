#pragma once

// Designed skills in the library: what `acrolab optimize --library FILE` stores beside its output
// folder — the skill file as written, the optimisation's result.json, the folder, the FIG code and
// its difficulty — per athlete, replaced when the athlete's skill of that name is designed again.

#include <cstdint>
#include <filesystem>

#include "acro/design/skill_file.h"
#include "acro/library/library.h"

namespace acro::library {

/// Stores `skill` (read from `skill_file`) with the result.json `acrolab optimize` wrote into
/// `output_dir`. Returns the design's id. Throws acro::InputError when a file cannot be read or the
/// skill's FIG code is malformed.
std::int64_t StoreSkillDesign(Library& library,
                              const std::filesystem::path& skill_file,
                              const analysis::Skill& skill,
                              const std::filesystem::path& output_dir);

}  // namespace acro::library
