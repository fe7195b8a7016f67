#include "acro/report/flights_chart.h"

#include <cmath>

namespace acro::ui {

Chart MakeImageFlightsChart(const vision::ImageFlights& flights) {
  Chart chart;
  chart.title = "flights from the picture: the soles against the bed's rest line";
  chart.x_label = "video time (s)";
  chart.y_label = "height above the bed's line (px)";
  chart.width_px = 1200;
  LineSeries soles, hips;
  soles.name = "soles (lowest foot keypoint)";
  hips.name = "centre of mass (keypoints, de Leva's masses)";
  hips.color = {0.17, 0.63, 0.17};
  for (Eigen::Index k = 0; k < flights.sole_y_px.size(); ++k) {
    const double t = double(k) / flights.rate_hz;
    const double rest = flights.bed.At(flights.sole_x_px[k]);  // the line under the soles
    soles.x.push_back(t);
    soles.y.push_back(rest - flights.sole_y_px[k]);
    hips.x.push_back(t);
    hips.y.push_back(rest - flights.com_y_px[k]);
  }
  chart.series = {soles, hips};
  for (const vision::ImageFlight& f : flights.flights) {
    if (!std::isfinite(f.takeoff_s) || !std::isfinite(f.landing_s)) continue;
    ShadedInterval band;
    band.x0 = f.takeoff_s;
    band.x1 = f.landing_s;
    band.color = {0.12, 0.47, 0.71};
    band.alpha = 0.15;
    band.label = "flight (take-off to landing)";
    chart.bands.push_back(band);
  }
  ReferenceLine line;
  line.y = 0;
  line.label = "the bed at rest";
  chart.reference_lines.push_back(line);
  return chart;
}

}  // namespace acro::ui
