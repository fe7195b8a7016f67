#pragma once

// One scored element as JSON, shared by jumps.json (each jump's "score") and score.json.

#include <nlohmann/json.hpp>

#include "acro/fig/score_sheet.h"

namespace acro::analysis {

nlohmann::ordered_json ElementScoreJson(const fig::ScoredElement& element);

}  // namespace acro::analysis
