#include "acro/report/progress_report.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <sstream>

#include <fmt/format.h>

#include "acro/base/file_io.h"
#include "acro/base/text_format.h"
#include "acro/fig/trampoline.h"
#include "html_page.h"

namespace acro::ui {

namespace {

// The FIG bed (4.28 m × 2.14 m) and its zone A (2.15 m × 1.08 m about the centre), in the bed's
// frame as jumps.json's landing_in_bed_m: x along the bed's length.
constexpr double kBedHalfLength = fig::kBedLength_m / 2, kBedHalfWidth = fig::kBedWidth_m / 2;
constexpr double kZoneHalfLength = fig::kZoneALength_m / 2, kZoneHalfWidth = fig::kZoneAWidth_m / 2;

LineSeries Rectangle(const std::string& name, double hx, double hy, Rgb color, bool dashed) {
  LineSeries s;
  s.name = name;
  s.x = {-hx, hx, hx, -hx, -hx};
  s.y = {-hy, -hy, hy, hy, -hy};
  s.color = color;
  s.width_px = 1.5;
  s.dashed = dashed;
  return s;
}

std::string Title(const library::Progress& p) {
  return p.athlete + (p.fig_code.empty() ? std::string(", every skill") : ", " + p.fig_code);
}

}  // namespace

namespace {

// The metric over the season: each jump (routine, element), each session's median, the trend.
ProgressFigure MetricFigure(const library::Progress& p, const std::string& x_label) {
  Chart c;
  c.title = fmt::format("{}: {} over the season", Title(p), p.metric_name);
  c.x_label = x_label;
  c.y_label = fmt::format("{} ({})", p.metric_name, p.unit);
  const bool per_routine = p.metric == library::ProgressMetric::kRoutineTime ||
                           p.metric == library::ProgressMetric::kRoutineDisplacement;
  const bool per_element = p.metric == library::ProgressMetric::kFaults;
  LineSeries jumps;
  jumps.name = per_routine ? "each routine" : per_element ? "each element" : "each jump";
  jumps.line = false;
  jumps.markers = true;
  jumps.color = {0.55, 0.65, 0.8};
  for (const library::ProgressPoint& q : p.points) {
    jumps.x.push_back(q.day);
    jumps.y.push_back(q.value);
  }
  LineSeries medians;
  medians.name =
      p.metric == library::ProgressMetric::kVerdict ? "session pass fraction" : "session median";
  medians.markers = true;
  medians.color = {0.12, 0.35, 0.7};
  for (const library::SessionProgress& s : p.sessions) {
    medians.x.push_back(s.day);
    medians.y.push_back(s.median);
  }
  LineSeries trend;
  trend.name = fmt::format(
      "trend {:+.3g} {} per 30 days (R² {:.2f})", 30 * p.trend_slope_per_day, p.unit, p.trend_r2);
  trend.dashed = true;
  trend.color = {0.85, 0.33, 0.1};
  const double last = p.sessions.back().day;
  trend.x = {0.0, last};
  trend.y = {p.trend_intercept, p.trend_intercept + p.trend_slope_per_day * last};
  c.series = {jumps, medians, trend};
  if (last <= 0) c.x_range = ValueRange{-1.0, 1.0};
  return {"progress_metric.png",
          p.metric == library::ProgressMetric::kVerdict
              ? fmt::format("Each jump's physical check, 1 passed and 0 failed, the "
                            "share of each session's jumps that passed, and the trend "
                            "line through the jumps ({} jumps in {} sessions).",
                            p.points.size(),
                            p.sessions.size())
              : fmt::format("Each {0}'s {1}, the median of each session and the "
                            "trend line through the {0}s ({2} {0}s in {3} sessions).",
                            per_routine   ? "routine"
                            : per_element ? "element"
                                          : "jump",
                            p.metric_name,
                            p.points.size(),
                            p.sessions.size()),
          c};
}

// The season's most frequent execution faults, per session: how many of its elements had each.
ProgressFigure FaultsFigure(const library::Progress& p, const std::string& x_label) {
  Chart c;
  c.title = Title(p) + ": the most frequent execution faults";
  c.x_label = x_label;
  c.y_label = "share of the session's elements";
  const std::array<std::array<double, 3>, 3> colors = {
      {{0.8, 0.15, 0.1}, {0.95, 0.55, 0.1}, {0.45, 0.3, 0.7}}};
  for (size_t k = 0; k < std::min<size_t>(3, p.fault_counts.size()); ++k) {
    LineSeries f;
    f.name =
        fmt::format("{} ({} in the season)", p.fault_counts[k].first, p.fault_counts[k].second);
    f.markers = true;
    f.color = {colors[k][0], colors[k][1], colors[k][2]};
    for (const library::SessionProgress& s : p.sessions) {
      if (s.elements == 0) continue;
      const auto it = s.fault_counts.find(p.fault_counts[k].first);
      f.x.push_back(s.day);
      f.y.push_back(double(it == s.fault_counts.end() ? 0 : it->second) / double(s.elements));
    }
    c.series.push_back(f);
  }
  if (p.sessions.back().day <= 0) c.x_range = ValueRange{-1.0, 1.0};
  c.y_range = ValueRange{0.0, 1.05};
  return {"progress_faults.png",
          fmt::format("The season's most frequent execution faults (reported beyond the "
                      "measurement's uncertainty, docs/scoring.md): the share of each "
                      "session's elements that had each ({} elements in all).",
                      p.elements),
          c};
}

// Landings: the season in three parts, so that a drift shows as a colour.
ProgressFigure LandingsFigure(const library::Progress& p) {
  Chart c;
  c.title = Title(p) + ": landings on the bed";
  c.x_label = "along the bed (m)";
  c.y_label = "across the bed (m)";
  c.width_px = 900;
  c.height_px = 520;
  c.x_range = ValueRange{-kBedHalfLength, kBedHalfLength};
  c.y_range = ValueRange{-kBedHalfWidth - 0.3, kBedHalfWidth + 0.3};
  c.series.push_back(Rectangle("bed", kBedHalfLength, kBedHalfWidth, {0.3, 0.3, 0.3}, false));
  c.series.push_back(Rectangle("zone A", kZoneHalfLength, kZoneHalfWidth, {0.1, 0.6, 0.2}, true));
  const Rgb colours[3] = {{0.65, 0.75, 0.9}, {0.2, 0.45, 0.8}, {0.75, 0.1, 0.15}};
  const size_t n = p.sessions.size();
  const size_t parts = std::min<size_t>(3, n);
  for (size_t part = 0; part < parts; ++part) {
    const size_t first = part * n / parts, last = (part + 1) * n / parts;  // [first, last)
    LineSeries s;
    s.line = false;
    s.markers = true;
    s.color = colours[parts == 1 ? 2 : part * 2 / (parts - 1)];
    for (size_t k = first; k < last; ++k) {
      s.x.insert(s.x.end(), p.sessions[k].landing_x_m.begin(), p.sessions[k].landing_x_m.end());
      s.y.insert(s.y.end(), p.sessions[k].landing_y_m.begin(), p.sessions[k].landing_y_m.end());
    }
    s.name = first + 1 == last
                 ? p.sessions[first].date
                 : fmt::format("{} – {}", p.sessions[first].date, p.sessions[last - 1].date);
    if (!s.x.empty()) c.series.push_back(s);
  }
  return {"progress_landings.png",
          "Landing points in the bed's frame (x along its length), by part of the "
          "season; the dashed rectangle is the FIG zone A (2.15 m × 1.08 m).",
          c};
}

// The share of each session's landings inside zone A.
ProgressFigure ZoneAFigure(const library::Progress& p, const std::string& x_label) {
  Chart z;
  z.title = Title(p) + ": landings in zone A";
  z.x_label = x_label;
  z.y_label = "landings in zone A (fraction)";
  z.y_range = ValueRange{0.0, 1.05};
  LineSeries share;
  share.name = "per session";
  share.markers = true;
  for (const library::SessionProgress& s : p.sessions) {
    if (s.landing_x_m.empty()) continue;
    share.x.push_back(s.day);
    share.y.push_back(double(s.landings_in_zone_a) / double(s.landing_x_m.size()));
  }
  z.series = {share};
  if (p.sessions.back().day <= 0) z.x_range = ValueRange{-1.0, 1.0};
  return {"progress_zone_a.png", "The share of each session's landings inside zone A.", z};
}

}  // namespace

std::vector<ProgressFigure> MakeProgressFigures(const library::Progress& p) {
  const std::string x_label = "days since " + p.first_date;
  std::vector<ProgressFigure> figures = {MetricFigure(p, x_label)};
  if (!p.fault_counts.empty()) figures.push_back(FaultsFigure(p, x_label));
  size_t landings = 0;
  for (const library::SessionProgress& s : p.sessions) landings += s.landing_x_m.size();
  if (landings > 0) {
    figures.push_back(LandingsFigure(p));
    figures.push_back(ZoneAFigure(p, x_label));
  }
  return figures;
}

std::vector<ProgressFigure> MakeSessionLandingFigures(const library::Progress& p) {
  std::vector<ProgressFigure> out;
  for (const library::SessionProgress& s : p.sessions) {
    if (s.landing_x_m.empty()) continue;
    Chart c;
    c.title = s.date;
    c.x_label = "along (m)";
    c.y_label = "across (m)";
    c.width_px = 300;
    c.height_px = 190;
    c.show_legend = false;
    c.x_range = ValueRange{-kBedHalfLength, kBedHalfLength};
    c.y_range = ValueRange{-kBedHalfWidth, kBedHalfWidth};
    c.series.push_back(Rectangle("zone A", kZoneHalfLength, kZoneHalfWidth, {0.1, 0.6, 0.2}, true));
    LineSeries in_a, out_a;
    in_a.line = out_a.line = false;
    in_a.markers = out_a.markers = true;
    in_a.color = {0.2, 0.45, 0.8};
    out_a.color = {0.75, 0.1, 0.15};
    for (size_t k = 0; k < s.landing_x_m.size(); ++k) {
      const bool inside = std::abs(s.landing_x_m[k]) <= kZoneHalfLength &&
                          std::abs(s.landing_y_m[k]) <= kZoneHalfWidth;
      LineSeries& to = inside ? in_a : out_a;
      to.x.push_back(s.landing_x_m[k]);
      to.y.push_back(s.landing_y_m[k]);
    }
    for (LineSeries* series : {&in_a, &out_a})
      if (!series->x.empty()) c.series.push_back(*series);
    out.push_back({"landings_" + s.date + ".png",
                   fmt::format("{} of {} in zone A", s.landings_in_zone_a, s.landing_x_m.size()),
                   c});
  }
  return out;
}

std::string FormatProgressHtml(const library::Progress& p,
                               const std::vector<ProgressFigure>& figures,
                               const std::vector<ProgressFigure>& session_landings) {
  std::ostringstream h;
  const std::string title = "Acrolab: " + Title(p) + " — " + p.metric_name;
  h << internal::HtmlPageStart(title, 960);
  h << "<h1>" << HtmlEscape(Title(p)) << "</h1>\n";
  std::string metric = p.metric_name;
  if (!metric.empty() && metric[0] >= 'a' && metric[0] <= 'z')
    metric[0] = char(metric[0] - 'a' + 'A');
  h << "<p>" << HtmlEscape(metric) << " (" << HtmlEscape(p.unit) << ") over " << p.sessions.size()
    << " sessions from " << p.sessions.front().date << " to " << p.sessions.back().date << ", "
    << p.points.size() << " jumps. Trend: " << fmt::format("{:+.3g}", 30 * p.trend_slope_per_day)
    << " " << HtmlEscape(p.unit) << " per 30 days (R² " << fmt::format("{:.2f}", p.trend_r2)
    << ").</p>\n";
  if (p.elements > 0) {
    h << "<p>Execution over the season: " << p.elements << " elements; ";
    if (p.fault_counts.empty()) {
      h << "no fault reported.";
    } else {
      h << "most frequent fault <b>" << HtmlEscape(p.fault_counts.front().first) << "</b> ("
        << p.fault_counts.front().second << " elements)";
      for (size_t k = 1; k < std::min<size_t>(4, p.fault_counts.size()); ++k)
        h << ", then " << HtmlEscape(p.fault_counts[k].first) << " (" << p.fault_counts[k].second
          << ")";
      h << ".";
    }
    h << "</p>\n";
  }
  for (const ProgressFigure& f : figures) {
    std::string svg = f.file.substr(0, f.file.size() - 4) + ".svg";
    h << "<figure><a href=\"" << HtmlEscape(svg) << "\"><img src=\"" << HtmlEscape(f.file)
      << "\" alt=\"" << HtmlEscape(f.chart.title) << "\"></a><figcaption>" << HtmlEscape(f.caption)
      << " (<a href=\"" << HtmlEscape(svg) << "\">SVG</a>)</figcaption></figure>\n";
  }
  if (!session_landings.empty()) {
    h << "<h2>Landings per session</h2>\n<p>Each session's landings on the bed (blue in zone A, "
         "red outside; the dashed rectangle is zone A).</p>\n<div style=\"display:flex;flex-wrap:"
         "wrap;gap:6px\">\n";
    for (const ProgressFigure& f : session_landings)
      h << "<figure style=\"margin:0\"><img src=\"" << HtmlEscape(f.file) << "\" alt=\""
        << HtmlEscape(f.chart.title) << "\" width=\"300\"><figcaption>" << HtmlEscape(f.caption)
        << "</figcaption></figure>\n";
    h << "</div>\n";
  }
  h << "<h2>Sessions</h2>\n<table><tr><th class=\"l\">date</th><th>jumps</th><th>"
    << (p.metric == library::ProgressMetric::kVerdict ? "passed" : "median") << "</th><th>min</th>"
    << "<th>max</th><th>landings in zone A</th><th>elements</th><th>faults</th>"
    << "<th class=\"l\">most frequent</th></tr>\n";
  for (const library::SessionProgress& s : p.sessions)
    h << "<tr><td class=\"l\">" << s.date << "</td><td>" << s.num_jumps << "</td><td>"
      << fmt::format("{:.3f}", s.median) << "</td><td>" << fmt::format("{:.3f}", s.min)
      << "</td><td>" << fmt::format("{:.3f}", s.max) << "</td><td>"
      << (s.landing_x_m.empty()
              ? std::string("–")
              : fmt::format("{} of {}", s.landings_in_zone_a, s.landing_x_m.size()))
      << "</td><td>" << s.elements << "</td><td>" << s.faults_reported << "</td><td class=\"l\">"
      << (s.most_frequent_fault.empty() ? std::string("–")
                                        : HtmlEscape(s.most_frequent_fault) + " (" +
                                              std::to_string(s.most_frequent_count) + ")")
      << "</td></tr>\n";
  h << "</table>\n<p>The table as CSV: <a href=\"progress.csv\">progress.csv</a>.</p>\n"
    << internal::kHtmlPageEnd;
  return h.str();
}

void WriteProgressReport(const library::Progress& progress, const std::filesystem::path& dir) {
  const std::vector<ProgressFigure> figures = MakeProgressFigures(progress);
  for (const ProgressFigure& f : figures) {
    std::filesystem::path png = dir / f.file;
    WriteChart(f.chart, png);
    WriteChart(f.chart, png.replace_extension(".svg"));
  }
  const std::vector<ProgressFigure> sessions = MakeSessionLandingFigures(progress);
  for (const ProgressFigure& f : sessions) WriteChart(f.chart, dir / f.file);
  WriteFileAtomically(dir / "progress.csv", library::FormatProgressCsv(progress));
  WriteFileAtomically(dir / "progress.html", FormatProgressHtml(progress, figures, sessions));
}

}  // namespace acro::ui
