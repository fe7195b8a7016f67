#include "acro/library/add_trial.h"

#include <algorithm>
#include <chrono>
#include <ctime>
#include <system_error>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "acro/athlete/athlete_profile.h"
#include "acro/base/content_hash.h"
#include "acro/base/file_io.h"
#include "acro/base/input_error.h"
#include "acro/base/version.h"
#include "acro/pipeline/steps.h"
#include "acro/pipeline/trial_input.h"
#include "json_text.h"

namespace acro::library {

namespace {

using Json = nlohmann::json;

std::string ReadText(const std::filesystem::path& path, std::int64_t max_bytes) {
  const std::vector<std::uint8_t> bytes = ReadFileBytes(path, max_bytes);
  return std::string(bytes.begin(), bytes.end());
}

std::filesystem::path Absolute(const std::filesystem::path& p) {
  if (p.empty()) return p;
  std::error_code ec;
  const std::filesystem::path abs = std::filesystem::weakly_canonical(p, ec);
  return ec ? std::filesystem::absolute(p).lexically_normal() : abs;
}

// An analysis directory: its provenance (which Acrolab, which trial content) and its jumps.
struct ImportedAnalysis {
  std::string version;
  std::string trial_sha256;
  /// An analysis of videos or detections: the SHA-256 of its primary input (analysis.json's
  /// "inputs" entry whose path is its "trial": the one video, or the first camera's), empty for
  /// a trial's own analysis.
  std::string primary_sha256;
  std::string jumps_json;
};

ImportedAnalysis ReadAnalysisDirectory(const std::filesystem::path& dir) {
  const std::filesystem::path provenance = dir / "analysis.json";
  if (!PathExists(provenance))
    throw InputError(provenance.string(),
                     "",
                     "missing: not an analysis directory of acrolab analyze (0.1.0 or later)");
  ImportedAnalysis out;
  Json doc = internal::ParseJsonText(ReadText(provenance, 1 << 20), provenance.string());
  for (const char* key : {"acrolab_version", "trial_sha256"})
    if (!doc.is_object() || !doc.contains(key) || !doc[key].is_string())
      throw InputError(provenance.string(), key, "missing or not text");
  out.version = doc["acrolab_version"].get<std::string>();
  out.trial_sha256 = doc["trial_sha256"].get<std::string>();
  if (doc.contains("inputs")) {
    const Json& inputs = doc["inputs"];
    if (!inputs.is_array()) throw InputError(provenance.string(), "inputs", "not a list");
    for (size_t i = 0; i < inputs.size(); ++i) {
      const Json& f = inputs[i];
      if (!f.is_object() || !f.contains("sha256") || !f["sha256"].is_string())
        throw InputError(
            provenance.string(), fmt::format("inputs[{}].sha256", i), "missing or not text");
      if (f.contains("path") && doc.contains("trial") && f["path"] == doc["trial"])
        out.primary_sha256 = f["sha256"].get<std::string>();
    }
  }
  out.jumps_json = ReadText(dir / "jumps.json", std::int64_t(256) << 20);
  return out;
}

}  // namespace

std::string FileDate(const std::filesystem::path& path) {
  std::error_code ec;
  const auto written = std::filesystem::last_write_time(path, ec);
  if (ec) throw InputError(path.string(), "", "cannot read its date: " + ec.message());
  const auto system = std::chrono::file_clock::to_sys(written);
  const std::time_t t = std::chrono::system_clock::to_time_t(system);
  std::tm tm{};
  localtime_r(&t, &tm);
  char text[16];
  std::strftime(text, sizeof text, "%Y-%m-%d", &tm);
  return text;
}

AddResult PlanAdd(const Library& library, const AddRequest& request) {
  AddResult result;
  const std::filesystem::path trial = Absolute(request.trial);
  if (!IsRegularFile(trial)) throw InputError(request.trial.string(), "", "no such file");
  result.path = trial.string();
  result.sha256 = Sha256OfFile(trial);
  const StoredState stored = library.FindTrial(result.path);
  if (!stored.stored) {
    result.outcome = AddOutcome::kAdded;
    return result;
  }
  result.outcome = AddOutcome::kReanalysed;
  if (stored.sha256 != result.sha256)
    result.why = "the file changed since it was stored";
  else if (request.analysis_dir.empty() && stored.analysis_version != AcrolabVersion())
    result.why =
        fmt::format("stored by Acrolab {}, this is {}", stored.analysis_version, AcrolabVersion());
  else if (!request.analysis_dir.empty() &&
           stored.analysis_source != Absolute(request.analysis_dir).string())
    result.why = "another analysis directory";
  else if (request.force)
    result.why = "forced";
  else
    result.outcome = AddOutcome::kUnchanged;
  return result;
}

AddResult AddTrial(Library& library, const AddRequest& request, const AddOptions& options) {
  AddResult result = PlanAdd(library, request);
  if (result.outcome == AddOutcome::kUnchanged) return result;
  if (request.athlete_profile.empty())
    throw InputError(request.trial.string(), "", "no athlete profile (--athlete FILE.yaml)");
  const analysis::AthleteProfile profile = analysis::ReadAthleteProfile(request.athlete_profile);

  TrialToStore t;
  t.athlete = profile.name;
  t.athlete_profile = ReadText(request.athlete_profile, 16 << 20);
  t.athlete_profile_path = Absolute(request.athlete_profile).string();
  t.stature_m = profile.height_m;
  t.mass_kg = profile.mass_kg;
  t.session_date = request.session_date.empty() ? FileDate(result.path) : request.session_date;
  t.session_place = request.session_place;
  t.session_notes = request.session_notes;
  t.path = result.path;
  t.sha256 = result.sha256;
  t.size_bytes = static_cast<std::int64_t>(std::filesystem::file_size(result.path));
  for (const auto& [from, to] :
       {std::pair{&request.video, &t.video_path}, {&request.calibration, &t.calibration_path}}) {
    if (from->empty()) continue;
    if (!IsRegularFile(*from))
      throw InputError(from->string(), "", "no such file (attached to " + result.path + ")");
    *to = Absolute(*from).string();
  }
  if (!request.analysis_dir.empty()) {
    // An analysis made elsewhere: it must be of this content.
    const ImportedAnalysis imported = ReadAnalysisDirectory(request.analysis_dir);
    // The trial's own analysis, or one of videos or detections whose primary input (the one
    // video, the first camera's — not a calibration, not the other cameras: a routine is stored
    // once) is this file.
    const bool read_it =
        imported.trial_sha256 == result.sha256 ||
        (!imported.primary_sha256.empty() && imported.primary_sha256 == result.sha256);
    if (!read_it)
      throw InputError((request.analysis_dir / "analysis.json").string(),
                       "trial_sha256",
                       fmt::format("{}… is not {}'s content ({}…), nor is its primary input: an "
                                   "analysis of another file",
                                   imported.trial_sha256.substr(0, 12),
                                   result.path,
                                   result.sha256.substr(0, 12)));
    t.analysis_version = imported.version;
    t.analysis_source = Absolute(request.analysis_dir).string();
    t.jumps_json = imported.jumps_json;
  } else {
    // The pipeline's input, as `analyze` opens it: read once, hashed, upright, the athlete's body.
    pipeline::TrialRequest open;
    open.trial = result.path;
    open.athlete.profile = request.athlete_profile;
    const pipeline::TrialInput input = pipeline::OpenTrial(open);
    if (input.sha256 != result.sha256)
      throw InputError(result.path, "", "the file changed while it was being added: add it again");
    if (options.warn)
      for (const std::string& w : input.warnings) options.warn(w);
    const analysis::TrialAnalysis analysed = pipeline::Analyze(input, options.analysis);
    if (options.warn)
      for (const std::string& w : analysed.warnings) options.warn(w);
    pipeline::DemandAFlight(input, analysed);  // a season holds jumps
    t.analysis_version = AcrolabVersion();
    t.analysis_source = "analysed";
    t.jumps_json = analysis::FormatJumpsJson(analysed);
  }
  result.trial_id = library.StoreTrial(t);
  const std::vector<JumpRecord> jumps = ParseJumpsJson(t.jumps_json, result.path);
  result.verdict = TrialVerdict(jumps);
  result.num_jumps = static_cast<int>(jumps.size());
  return result;
}

}  // namespace acro::library
