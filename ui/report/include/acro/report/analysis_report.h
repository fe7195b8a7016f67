#pragma once

// The report of `acrolab analyze`: one HTML page a coach can read — routine summary, per-jump
// table, the physical-correctness verdict with its cause, and charts (COM height with the phases,
// root residuals, angular momentum, the angle and torque of one joint) as PNG and SVG. The charts
// are built as plain data (chart.h) from the analysis, so their content is testable without
// rendering; rendering needs no display.

#include <filesystem>
#include <string>
#include <vector>

#include "acro/assess/trial_analysis.h"
#include "acro/report/chart.h"

namespace acro::ui {

struct AnalysisReportOptions {
  /// The coordinate whose angle and torque are plotted (MakeCoordinateNames).
  std::string joint = "r_hip_flexion";
  std::string trial_path;  ///< as the user gave it, for the page's header
  std::string athlete;     ///< the athlete as the page names it
  /// Render the plots (false: the page only, with a note).
  bool render_images = true;
  /// With a calibrated video (`analyze --video`): the silhouette IoU per compared frame at these
  /// trial times (a chart), and the overlay video's file name in the output folder (shown on the
  /// page), each when not empty.
  std::vector<double> silhouette_time_s;
  std::vector<double> silhouette_iou;
  std::string overlay_video;
  /// Per jump (its index, 1-based), a filmstrip picture's file name in the output folder; or why
  /// there are none (shown as a note when not empty).
  std::vector<std::pair<int, std::string>> filmstrips;
  /// The same as videos (analyze --video), per jump index.
  std::vector<std::pair<int, std::string>> filmstrip_videos;
  std::string filmstrip_note;
};

/// One figure of the report: its chart and its file name in the output folder.
struct ReportFigure {
  std::string file;  ///< "com_height.png"
  std::string caption;
  Chart chart;
};

/// The report's figures. Throws acro::InputError when `options.joint` is not a joint coordinate
/// of the motion (naming it and the valid names' first few).
std::vector<ReportFigure> MakeAnalysisFigures(const analysis::TrialAnalysis& analysis,
                                              const AnalysisReportOptions& options);

struct AnalysisReportOutcome {
  bool images_rendered = false;
  std::string reason;  ///< why there are no images (one line), when there are none
  std::vector<std::filesystem::path> images;  ///< each figure's PNG, then its SVG
};

/// The HTML page (self-contained but for the PNG files it links, which `outcome` lists).
std::string FormatAnalysisReportHtml(const analysis::TrialAnalysis& analysis,
                                     const std::vector<ReportFigure>& figures,
                                     const AnalysisReportOptions& options,
                                     const AnalysisReportOutcome& outcome);

/// Renders the figures into `dir` (when asked and possible here) and writes dir/report.html, each
/// file atomically. Rendering failures do not stop the page: they come back in the outcome.
AnalysisReportOutcome WriteAnalysisReport(const analysis::TrialAnalysis& analysis,
                                          const std::filesystem::path& dir,
                                          const AnalysisReportOptions& options);

}  // namespace acro::ui
