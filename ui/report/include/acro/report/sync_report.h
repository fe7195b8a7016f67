#pragma once

// The cost of every offset an automatic sync tried, as a chart: how deep and how distinct its
// minimum is tells whether to trust it (`acrolab sync --plot`).

#include "acro/report/chart.h"
#include "acro/vision/sync.h"

namespace acro::ui {

/// Cost against offset, in frames of the video when `frame_s` > 0 (else seconds), with the offset
/// found shaded.
Chart MakeSyncCostChart(const vision::AutoSyncResult& result, double frame_s);

}  // namespace acro::ui
