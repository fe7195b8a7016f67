#include "acro/report/library_text.h"

#include <fmt/format.h>
#include <nlohmann/json.hpp>

namespace acro::ui {

std::string FormatAthleteTable(const std::vector<library::AthleteSummary>& athletes) {
  std::string out = fmt::format("{:<24} {:>8} {:>8} {:>9} {:>9} {:>7} {:>7}\n", "athlete", "stature", "mass",
                                "profiles", "sessions", "trials", "jumps");
  for (const library::AthleteSummary& a : athletes)
    out += fmt::format("{:<24} {:6.2f} m {:5.1f} kg {:9} {:9} {:7} {:7}\n", a.name, a.stature_m, a.mass_kg,
                       a.num_profiles, a.num_sessions, a.num_trials, a.num_jumps);
  return out;
}

std::string FormatDesignTable(const std::vector<library::DesignSummary>& designs, const std::string& library_path) {
  std::string out = fmt::format("{:>6}  {:<18} {:<8} {:<8} {:>5}  {:<20}  {}\n", "id", "athlete", "kind", "codes",
                                "DD", "created", "name");
  for (const library::DesignSummary& d : designs)
    out += fmt::format("{:6}  {:<18} {:<8} {:<8} {:5.1f}  {:<20}  {}\n", static_cast<long long>(d.id), d.athlete,
                       d.kind, d.codes, d.difficulty, d.created_at, d.name);
  out += fmt::format("{} designs in {}\n", designs.size(), library_path);
  return out;
}

std::string FormatTrialTable(const std::vector<library::TrialSummary>& trials, const std::string& library_path) {
  std::string out = fmt::format("{:>6}  {:<10}  {:<18} {:>5} {:>6} {:>8}  {:<10}  {}\n", "id", "date", "athlete",
                                "jumps", "DD", "ToF (s)", "verdict", "trial");
  for (const library::TrialSummary& t : trials)
    out += fmt::format("{:6}  {:<10}  {:<18} {:5} {:6.1f} {:8.3f}  {:<10}  {}\n", static_cast<long long>(t.id),
                       t.session_date, t.athlete, t.num_jumps, t.difficulty, t.time_of_flight_s, t.verdict, t.path);
  out += fmt::format("{} trials in {}\n", trials.size(), library_path);
  return out;
}

std::string FormatTrialListJson(const std::vector<library::TrialSummary>& trials) {
  nlohmann::json out = nlohmann::json::array();
  for (const library::TrialSummary& t : trials)
    out.push_back({{"id", t.id},
                   {"athlete", t.athlete},
                   {"date", t.session_date},
                   {"path", t.path},
                   {"sha256", t.sha256},
                   {"verdict", t.verdict},
                   {"jumps", t.num_jumps},
                   {"difficulty", t.difficulty},
                   {"time_of_flight_s", t.time_of_flight_s},
                   {"analysis_version", t.analysis_version}});
  return out.dump(1) + "\n";
}

std::string FormatTrialDetails(const library::TrialSummary& t, const std::string& jumps_json) {
  std::string out = fmt::format("trial {}: {}\n  athlete {}, session {}{}\n  SHA-256 {}, {} bytes\n",
                                static_cast<long long>(t.id), t.path, t.athlete, t.session_date,
                                t.session_place.empty() ? "" : ", " + t.session_place, t.sha256,
                                static_cast<long long>(t.size_bytes));
  if (!t.video_path.empty()) out += fmt::format("  video {}, calibration {}\n", t.video_path, t.calibration_path);
  out += fmt::format("  analysed {} by Acrolab {} ({}); verdict {}\n", t.analysed_at, t.analysis_version,
                     t.analysis_source, t.verdict);
  out += fmt::format("  {:>4} {:<6} {:<28} {:>8} {:>7} {:>7} {:>5}  {}\n", "jump", "code", "skill", "ToF (s)",
                     "HD (m)", "apex", "DD", "verdict");
  for (const library::JumpRecord& j : library::ParseJumpsJson(jumps_json, t.path))
    out += fmt::format("  {:4} {:<6} {:<28} {:8.3f} {:7.2f} {:7.2f} {:5.1f}  {}\n", j.index, j.fig_code, j.skill_name,
                       j.time_of_flight_s, j.displacement_m, j.apex_above_bed_m, j.difficulty, j.verdict);
  return out;
}

std::string FormatJumpRowTable(const std::vector<library::JumpRow>& rows, double query_ms) {
  std::string out = fmt::format("{:<10}  {:<16} {:>4} {:<6} {:>8} {:>7} {:>5}  {:<10}  {}\n", "date", "athlete",
                                "jump", "code", "ToF (s)", "HD (m)", "DD", "verdict", "trial");
  for (const library::JumpRow& r : rows)
    out += fmt::format("{:<10}  {:<16} {:4} {:<6} {:8.3f} {:7.2f} {:5.1f}  {:<10}  {}\n", r.session_date, r.athlete,
                       r.jump.index, r.jump.fig_code, r.jump.time_of_flight_s, r.jump.displacement_m,
                       r.jump.difficulty, r.jump.verdict_class, r.trial_path);
  out += fmt::format("{} jumps (query {:.1f} ms)\n", rows.size(), query_ms);
  return out;
}

std::string FormatLibraryExportJson(const library::Library& lib, const std::string& library_path) {
  nlohmann::json out;
  out["library"] = library_path;
  out["schema_version"] = lib.schema_version();
  out["trials"] = nlohmann::json::array();
  for (const library::TrialSummary& t : lib.ListTrials())
    out["trials"].push_back({{"id", t.id},
                             {"athlete", t.athlete},
                             {"date", t.session_date},
                             {"place", t.session_place},
                             {"path", t.path},
                             {"sha256", t.sha256},
                             {"video", t.video_path},
                             {"calibration", t.calibration_path},
                             {"analysis_version", t.analysis_version},
                             {"analysed_at", t.analysed_at},
                             {"verdict", t.verdict},
                             {"jumps", nlohmann::json::parse(lib.TrialJumpsJson(t.id))}});
  return out.dump(1) + "\n";
}

}  // namespace acro::ui
