#include "acro/pipeline/steps.h"

#include <ctime>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "acro/athlete/body_mesh.h"
#include "acro/base/input_error.h"
#include "acro/base/version.h"
#include "acro/scene/trial_scene.h"

namespace acro::pipeline {

analysis::TrialAnalysis Analyze(const TrialInput& input,
                                const analysis::TrialAnalysisOptions& options) {
  return analysis::AnalyzeTrial(input.trial,
                                input.static_trial ? &*input.static_trial : nullptr,
                                input.athlete.body,
                                options);
}

void DemandAFlight(const TrialInput& input, const analysis::TrialAnalysis& analysis) {
  if (!analysis.phases.flights.empty()) return;
  const capture::Trial& trial = input.trial;
  throw InputError(
      input.path.string(),
      "",
      fmt::format("no flight in its {} frames ({:.2f} s at {:g} Hz): the athlete's "
                  "centre of mass never leaves the bed, so there is no jump to measure "
                  "(acrolab reconstruct gives the joint angles of any motion)",
                  trial.num_frames,
                  trial.duration_s(),
                  trial.point_rate_hz));
}

VideoCheck CheckVideo(VideoInput& video,
                      const capture::Trial& trial,
                      const analysis::AthleteBody& body,
                      const analysis::TrialAnalysis& analysis,
                      const Progress& progress) {
  // The silhouettes with the body's full mesh: what the video shows.
  analysis::TrialScene scene(trial, analysis, body, analysis::MakeEllipsoidBodyMesh(body));
  VideoCheck out;
  out.sync = video.Sync(scene, progress);
  out.silhouettes = video.CheckSilhouettes(scene, progress);
  return out;
}

VideoCheck AttachVideo(VideoInput& video,
                       const TrialInput& input,
                       analysis::TrialAnalysis* analysis,
                       const Progress& progress) {
  VideoCheck out = CheckVideo(video, input.trial, input.athlete.body, *analysis, progress);
  analysis::AttachSilhouetteCheck(out.silhouettes, analysis);
  return out;
}

std::string FormatAnalysisProvenance(const TrialInput& input) {
  nlohmann::json o;  // keys in alphabetical order, as library add reads them
  o["acrolab_version"] = AcrolabVersion();
  const auto canonical = [](const std::filesystem::path& p) {
    std::error_code ec;
    const std::filesystem::path c = std::filesystem::weakly_canonical(p, ec);
    return (ec ? std::filesystem::absolute(p).lexically_normal() : c).string();
  };
  o["trial"] = canonical(input.path);
  o["trial_sha256"] = input.sha256;
  if (!input.inputs.empty()) {
    nlohmann::json list = nlohmann::json::array();
    for (const TrialInput::HashedFile& f : input.inputs)
      list.push_back({{"path", canonical(f.path)}, {"role", f.role}, {"sha256", f.sha256}});
    o["inputs"] = list;
  }
  o["athlete"] = input.athlete.name;
  const std::time_t now = std::time(nullptr);
  std::tm tm{};
  gmtime_r(&now, &tm);
  char text[32];
  std::strftime(text, sizeof text, "%Y-%m-%dT%H:%M:%SZ", &tm);
  o["analysed_at"] = text;
  return o.dump(1) + "\n";
}

}  // namespace acro::pipeline
