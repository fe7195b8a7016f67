#include "acro/report/sync_report.h"

namespace acro::ui {

Chart MakeSyncCostChart(const vision::AutoSyncResult& result, double frame_s) {
  const double unit = frame_s > 0 ? frame_s : 1.0;
  Chart chart;
  const bool detections = result.method == "detections";
  chart.title = "sync from " + result.method;
  chart.x_label = frame_s > 0 ? "offset (video frames)" : "offset (s)";
  chart.y_label = detections ? "mean distance to the detections (px, truncated)"
                             : "1 − correlation of motion and speed";
  LineSeries cost;
  cost.name = "cost";
  for (size_t i = 0; i < result.offsets_s.size(); ++i) {
    cost.x.push_back(result.offsets_s[i] / unit);
    cost.y.push_back(result.costs[i]);
  }
  cost.markers = cost.x.size() <= 200;
  chart.series.push_back(cost);
  ShadedInterval found;
  const double x = result.sync.offset_s / unit;
  const double half =
      frame_s > 0
          ? 0.5
          : 0.5 * (result.offsets_s.size() > 1 ? result.offsets_s[1] - result.offsets_s[0] : 0.01);
  found.x0 = x - half;
  found.x1 = x + half;
  found.color = {0.84, 0.15, 0.16};
  found.alpha = 0.3;
  found.label = "offset found";
  chart.bands.push_back(found);
  return chart;
}

}  // namespace acro::ui
