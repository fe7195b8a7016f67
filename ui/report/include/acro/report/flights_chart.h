#pragma once

// One video's flights found from the image (vision/image_flights.h) as a chart: the soles' and the
// hips' height above the bed's rest line in the picture over time, each flight shaded from its
// take-off to its landing — what a coach checks the timing against (`acrolab video flights`).

#include "acro/report/chart.h"
#include "acro/vision/image_flights.h"

namespace acro::ui {

Chart MakeImageFlightsChart(const vision::ImageFlights& flights);

}  // namespace acro::ui
