#pragma once

/// \file
/// The named steps every door runs on a TrialInput (docs/design.md, "One pipeline"): Analyze
/// (reconstruct, then assess), AttachVideo (sync, silhouettes, into the analysis), and the
/// provenance written beside the outputs. A door is then: parse its arguments, OpenTrial, the
/// steps it needs, its own outputs (ui draws them), print.

#include <string>

#include "acro/assess/trial_analysis.h"
#include "acro/base/progress.h"
#include "acro/pipeline/trial_input.h"
#include "acro/pipeline/video_input.h"

namespace acro::pipeline {

/// Reconstructs and assesses the trial for its athlete (analysis::AnalyzeTrial, with the static
/// trial when there is one).
analysis::TrialAnalysis Analyze(const TrialInput& input,
                                const analysis::TrialAnalysisOptions& options = {});

/// Throws acro::InputError naming the trial when the analysis found no flight (the markers never
/// leave the floor, or the trial is too short to hold one), with what it holds: for the doors that
/// measure jumps (`analyze`, `library add`), whose outputs would be empty. `reconstruct` gives the
/// joint angles of any motion.
void DemandAFlight(const TrialInput& input, const analysis::TrialAnalysis& analysis);

/// What AttachVideo found.
struct VideoCheck {
  SyncOutcome sync;
  analysis::SilhouetteCheck silhouettes;
};

/// The video against the analysis: the sync (as the video's request says; `auto` refined by the
/// silhouettes), then the silhouettes of the athlete — the body's full mesh — over every flight
/// frame.
VideoCheck CheckVideo(VideoInput& video,
                      const capture::Trial& trial,
                      const analysis::AthleteBody& body,
                      const analysis::TrialAnalysis& analysis,
                      const Progress& progress = {});

/// CheckVideo, its silhouettes recorded in `analysis` (each jump's median IoU).
VideoCheck AttachVideo(VideoInput& video,
                       const TrialInput& input,
                       analysis::TrialAnalysis* analysis,
                       const Progress& progress = {});

/// analysis.json: the Acrolab version, the trial's absolute path and the SHA-256 of the bytes
/// analysed (TrialInput::sha256, not a second read of the file), the athlete, when.
/// `library add --analysis DIR` reads it.
std::string FormatAnalysisProvenance(const TrialInput& input);

}  // namespace acro::pipeline
