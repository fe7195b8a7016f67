#pragma once

// The season's progress page (`acrolab library progress`): the metric over the season (one point
// per jump, the session medians, the trend line), the landings on the bed per part of the season
// with zone A drawn, the share of landings in zone A per session, each session's landings in a
// grid of small charts, and the sessions' table — as PNG and SVG charts, progress.csv and
// progress.html.

#include <filesystem>
#include <vector>

#include "acro/library/progress.h"
#include "acro/report/chart.h"

namespace acro::ui {

/// The charts of the page, as data (tested without rendering).
struct ProgressFigure {
  std::string file;  ///< PNG name; the SVG has the same stem
  std::string caption;
  Chart chart;
};
std::vector<ProgressFigure> MakeProgressFigures(const library::Progress& progress);

/// One small chart per session with landings: that session's landing points on the bed with zone
/// A (file `landings_YYYY-MM-DD.png`, caption "N of M in zone A"), for the page's grid.
std::vector<ProgressFigure> MakeSessionLandingFigures(const library::Progress& progress);

/// The HTML page linking the figures' files (and the sessions' landing charts, in a grid).
std::string FormatProgressHtml(const library::Progress& progress,
                               const std::vector<ProgressFigure>& figures,
                               const std::vector<ProgressFigure>& session_landings = {});

/// Writes DIR/progress.html, DIR/progress.csv and each figure as PNG and SVG. Throws
/// acro::InputError when a file cannot be written.
void WriteProgressReport(const library::Progress& progress, const std::filesystem::path& dir);

}  // namespace acro::ui
