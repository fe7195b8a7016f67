#include "acro/reconstruct/phases.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <string>

#include <fmt/format.h>

#include <Eigen/Dense>

#include "acro/base/demand.h"
#include "acro/base/input_error.h"

namespace acro::analysis {
namespace {

// Least-squares parabola z = c0 + c1 τ + c2 τ² over samples [first, last], τ = t − t_ref.
Eigen::Vector3d FitParabola(const Eigen::VectorXd& t,
                            const Eigen::VectorXd& z,
                            int first,
                            int last,
                            double t_ref,
                            double* rms) {
  const int n = last - first + 1;
  Eigen::MatrixXd A(n, 3);
  Eigen::VectorXd b(n);
  for (int i = 0; i < n; ++i) {
    const double tau = t[first + i] - t_ref;
    A.row(i) << 1.0, tau, tau * tau;
    b[i] = z[first + i];
  }
  const Eigen::Vector3d c = A.colPivHouseholderQr().solve(b);
  if (rms) *rms = std::sqrt((A * c - b).squaredNorm() / n);
  return c;
}

// Refines a take-off (side = −1) or landing (side = +1) instant near the free-fall run [run_first,
// run_last] whose trusted core is [core_first, core_last]. Model over a fixed window of samples:
// the flight parabola, plus on the contact side of t0 the terms s3 d³ + s4 d⁴ + s5 d⁵ with d = |t −
// t0|. A sprung bed's force grows from zero at t0 like sin(ω d) (d, d³ after integrating twice: d³,
// d⁵), damping adds even terms; s3 ≥ 0 because a support only pushes. t0 is scanned on a
// tenth-of-a-frame grid; each candidate is one linear least-squares solve over the same samples.
double RefineEvent(const Eigen::VectorXd& t,
                   const Eigen::VectorXd& z,
                   int run_first,
                   int run_last,
                   int core_first,
                   int core_last,
                   int side,
                   double dt,
                   const PhaseOptions& options) {
  const int n = static_cast<int>(t.size());
  // The free-fall run's edge lies within ~60 ms of the event (measured on simulated beds).
  const int margin = static_cast<int>(std::lround(0.06 / dt));
  const int window = static_cast<int>(std::lround(options.contact_fit_window_s / dt));
  int lo, hi;
  double search_from, search_to;
  if (side < 0) {
    search_from = t[std::max(0, run_first - margin)];
    search_to = t[core_first];
    lo = std::max(0, run_first - margin - window);
    hi = core_last;
  } else {
    search_from = t[core_last];
    search_to = t[std::min(n - 1, run_last + margin)];
    lo = core_first;
    hi = std::min(n - 1, run_last + margin + window);
  }
  const int rows = hi - lo + 1;
  const double t_ref = t[core_first];
  // Take-off: the bed pushes until its force is zero, so the departure starts with d³ (force ∝ d).
  // Landing: a damped bed's force can jump at touch-down, so the arrival may start with d².
  const int p0 = side < 0 ? 3 : 2;
  const int terms = side < 0 ? 2 : 3;
  Eigen::MatrixXd A(rows, 3 + terms);
  Eigen::VectorXd b(rows);
  for (int i = 0; i < rows; ++i) b[i] = z[lo + i];
  double best_t0 = side < 0 ? search_to : search_from;
  double best_sse = std::numeric_limits<double>::infinity();
  for (double t0 = search_from; t0 <= search_to + 1e-12; t0 += dt / 10) {
    int contact_rows = 0;
    for (int i = 0; i < rows; ++i) {
      const double ti = t[lo + i];
      const double tau = ti - t_ref;
      const double d = side < 0 ? std::max(0.0, t0 - ti) : std::max(0.0, ti - t0);
      contact_rows += d > 0;
      A(i, 0) = 1.0;
      A(i, 1) = tau;
      A(i, 2) = tau * tau;
      for (int k = 0; k < terms; ++k) A(i, 3 + k) = std::pow(d, p0 + k);
    }
    if (contact_rows < 4) continue;
    const Eigen::VectorXd c = A.colPivHouseholderQr().solve(b);
    if (c[3] < 0) continue;  // a support that pulls: not a contact
    const double sse = (A * c - b).squaredNorm();
    if (sse < best_sse) {
      best_sse = sse;
      best_t0 = t0;
    }
  }
  return best_t0;
}

// Fills the parabola fields of a flight from COM samples between its events.
void FitFlightParabola(const Eigen::VectorXd& t, const Eigen::VectorXd& z, Flight* flight) {
  int first = 0, last = static_cast<int>(t.size()) - 1;
  while (first <= last && t[first] < flight->takeoff_s) ++first;
  while (last >= first && t[last] > flight->landing_s) --last;
  if (last - first < 3) return;
  const Eigen::Vector3d c =
      FitParabola(t, z, first, last, flight->takeoff_s, &flight->parabola_rms_m);
  flight->fitted_gravity_m_per_s2 = -2.0 * c[2];
  flight->takeoff_vertical_velocity_m_per_s = c[1];
  const double tau_apex = c[2] < 0 ? -c[1] / (2 * c[2]) : 0.0;
  flight->apex_s = flight->takeoff_s + tau_apex;
  flight->apex_z_m = c[0] + c[1] * tau_apex + c[2] * tau_apex * tau_apex;
}

int FirstFrameAtOrAfter(const Eigen::VectorXd& t, double time) {
  int i = 0;
  while (i < t.size() && t[i] < time - 1e-12) ++i;
  return i;
}

}  // namespace

bool PhaseOptions::IsValid(std::string* why) const {
  auto fail = [&](const char* what) {
    if (why) *why = what;
    return false;
  };
  if (!(gravity_m_per_s2 > 0)) return fail("gravity_m_per_s2 must be positive");
  if (!(smoothing_half_window_s > 0)) return fail("smoothing_half_window_s must be positive");
  if (!(free_fall_tolerance_m_per_s2 > 0))
    return fail("free_fall_tolerance_m_per_s2 must be positive");
  if (!(min_flight_s > 0)) return fail("min_flight_s must be positive");
  if (!(contact_fit_window_s > 0)) return fail("contact_fit_window_s must be positive");
  if (!(force_threshold_N > 0)) return fail("force_threshold_N must be positive");
  if (!std::isfinite(feet_clearance_m)) return fail("feet_clearance_m must be a number");
  if (!(feet_bridge_s >= 0)) return fail("feet_bridge_s must be non-negative");
  return true;
}

Eigen::VectorXd SavitzkyGolaySecondDerivative(const Eigen::VectorXd& values,
                                              double dt,
                                              int half_window) {
  const int n = static_cast<int>(values.size());
  Eigen::VectorXd out = Eigen::VectorXd::Constant(n, std::numeric_limits<double>::quiet_NaN());
  const int h = std::max(1, half_window);
  if (n < 2 * h + 1) return out;
  // Quadratic least-squares weights for the second derivative over 2h+1 equally spaced samples:
  // w_k = (k² − h(h+1)/3) / (Σ k⁴ − (Σ k²)² / (2h+1)), second derivative = 2 Σ w_k y_k / dt².
  double s2 = 0, s4 = 0;
  for (int k = -h; k <= h; ++k) {
    s2 += k * k;
    s4 += double(k) * k * k * k;
  }
  const double m = 2 * h + 1;
  const double denominator = s4 - s2 * s2 / m;
  Eigen::VectorXd w(2 * h + 1);
  for (int k = -h; k <= h; ++k) w[k + h] = (k * k - s2 / m) / denominator;
  for (int i = 0; i < n; ++i) {
    const int centre = std::clamp(i, h, n - 1 - h);
    double acc = 0;
    for (int k = -h; k <= h; ++k) acc += w[k + h] * values[centre + k];
    out[i] = 2 * acc / (dt * dt);
  }
  return out;
}

PhaseSegmentation DetectFlightsFromCom(const Eigen::VectorXd& time_s,
                                       const Eigen::VectorXd& com_z_m,
                                       const PhaseOptions& options) {
  DemandValidOptions(options, "phase options");
  ACRO_DEMAND(time_s.size() == com_z_m.size());
  PhaseSegmentation result;
  result.method = "com";
  const int n = static_cast<int>(time_s.size());
  if (n < 8) return result;
  const double dt = (time_s[n - 1] - time_s[0]) / (n - 1);
  const int h = std::max(2, static_cast<int>(std::lround(options.smoothing_half_window_s / dt)));
  const Eigen::VectorXd a = SavitzkyGolaySecondDerivative(com_z_m, dt, h);

  // Free-fall runs. A support only pushes, so in contact a ≥ −g: free fall is a ≤ −g + tolerance
  // (one sided; lower values are noise). Short interruptions whose mean acceleration stays below
  // zero are noise too (a real contact pushes with several body weights) and are bridged.
  const double g = options.gravity_m_per_s2;
  const int min_frames = static_cast<int>(std::ceil(options.min_flight_s / dt));
  auto falling = [&](int k) {
    return !std::isnan(com_z_m[k]) && a[k] <= -g + options.free_fall_tolerance_m_per_s2;
  };
  int i = 0;
  while (i < n) {
    if (!falling(i)) {
      ++i;
      continue;
    }
    int j = i;
    while (true) {
      while (j + 1 < n && falling(j + 1)) ++j;
      int k = j + 1;
      double sum = 0;
      while (k < n && k <= j + 2 * h && !falling(k) && !std::isnan(com_z_m[k])) sum += a[k++];
      if (k < n && k <= j + 2 * h && falling(k) && sum / (k - j - 1) < 0) {
        j = k;
        continue;
      }
      break;
    }
    const int first = i, last = j;
    i = j + 1;
    if (last - first + 1 < min_frames) continue;
    Flight flight;
    flight.partial = first <= h || last >= n - 1 - h;
    const int core_first = std::min(last, first + h);
    const int core_last = std::max(first, last - h);
    flight.takeoff_s =
        first <= h
            ? time_s[0]
            : RefineEvent(time_s, com_z_m, first, last, core_first, core_last, -1, dt, options);
    flight.landing_s =
        last >= n - 1 - h
            ? time_s[n - 1]
            : RefineEvent(time_s, com_z_m, first, last, core_first, core_last, +1, dt, options);
    flight.takeoff_frame = FirstFrameAtOrAfter(time_s, flight.takeoff_s);
    flight.landing_frame = FirstFrameAtOrAfter(time_s, flight.landing_s);
    FitFlightParabola(time_s, com_z_m, &flight);
    result.flights.push_back(flight);
  }
  return result;
}

namespace {

// Flights as the runs where `signal` ≤ `threshold` (at least min_flight_s long), their events at
// the interpolated crossings; contact interruptions shorter than `bridge_s` inside a run are noise
// and are bridged. The COM (when given) supplies the frames and the parabola.
PhaseSegmentation FlightsBelowThreshold(const Eigen::VectorXd& time_s,
                                        const Eigen::VectorXd& signal,
                                        double threshold,
                                        double bridge_s,
                                        const Eigen::VectorXd& com_time_s,
                                        const Eigen::VectorXd& com_z_m,
                                        const PhaseOptions& options) {
  PhaseSegmentation result;
  const int n = static_cast<int>(time_s.size());
  if (n < 4) return result;
  const double dt = (time_s[n - 1] - time_s[0]) / (n - 1);
  const int min_samples = static_cast<int>(std::ceil(options.min_flight_s / dt));
  const int bridge = static_cast<int>(std::floor(bridge_s / dt));
  // Linear interpolation of the threshold crossing between samples k and k+1.
  auto crossing = [&](int k) {
    const double f0 = signal[k], f1 = signal[k + 1];
    const double s = f1 != f0 ? (threshold - f0) / (f1 - f0) : 0.5;
    return time_s[k] + std::clamp(s, 0.0, 1.0) * (time_s[k + 1] - time_s[k]);
  };
  int i = 0;
  while (i < n) {
    if (signal[i] > threshold) {
      ++i;
      continue;
    }
    int j = i;
    for (;;) {
      while (j + 1 < n && signal[j + 1] <= threshold) ++j;
      // A short excursion above the threshold followed by more flight: bridge it.
      int k = j + 1;
      while (k < n && signal[k] > threshold && k - j <= bridge) ++k;
      if (k < n && k - j <= bridge && signal[k] <= threshold) {
        j = k;
        continue;
      }
      break;
    }
    const int first = i, last = j;
    i = j + 1;
    if (last - first + 1 < min_samples) continue;
    Flight flight;
    flight.partial = first == 0 || last == n - 1;
    flight.takeoff_s = first == 0 ? time_s[0] : crossing(first - 1);
    flight.landing_s = last == n - 1 ? time_s[n - 1] : crossing(last);
    if (com_time_s.size() > 0) {
      flight.takeoff_frame = FirstFrameAtOrAfter(com_time_s, flight.takeoff_s);
      flight.landing_frame = FirstFrameAtOrAfter(com_time_s, flight.landing_s);
      if (com_z_m.size() > 0) FitFlightParabola(com_time_s, com_z_m, &flight);
    }
    result.flights.push_back(flight);
  }
  return result;
}

}  // namespace

PhaseSegmentation DetectFlightsFromForce(const Eigen::VectorXd& time_s,
                                         const Eigen::VectorXd& force_z_N,
                                         const Eigen::VectorXd& com_time_s,
                                         const Eigen::VectorXd& com_z_m,
                                         const PhaseOptions& options) {
  DemandValidOptions(options, "phase options");
  ACRO_DEMAND(time_s.size() == force_z_N.size());
  const int n = static_cast<int>(time_s.size());
  if (n < 4) return PhaseSegmentation{{}, "force plates"};
  // The flight baseline: unloaded plates read their offset. Take the median of the lowest tenth of
  // the samples as that offset (flight is where the force is smallest).
  std::vector<double> sorted(force_z_N.data(), force_z_N.data() + n);
  std::sort(sorted.begin(), sorted.end());
  const double baseline = sorted[static_cast<std::size_t>(n / 20)];
  PhaseSegmentation result = FlightsBelowThreshold(
      time_s, force_z_N, baseline + options.force_threshold_N, 0.0, com_time_s, com_z_m, options);
  result.method = "force plates";
  return result;
}

PhaseSegmentation DetectFlightsFromIntervals(
    const std::vector<std::pair<double, double>>& flights_s,
    const Eigen::VectorXd& time_s,
    const Eigen::VectorXd& com_z_m,
    const std::string& method,
    const PhaseOptions& options) {
  DemandValidOptions(options, "phase options");
  ACRO_DEMAND(com_z_m.size() == time_s.size() || com_z_m.size() == 0);
  PhaseSegmentation result{{}, method};
  const Eigen::Index n = time_s.size();
  if (n < 2) return result;
  const double first = time_s[0], last = time_s[n - 1];
  for (const auto& [takeoff, landing] : flights_s) {
    // An end outside the recording (or not seen) is where the recording cuts the flight.
    Flight flight;
    flight.takeoff_s = std::isfinite(takeoff) ? std::clamp(takeoff, first, last) : first;
    flight.landing_s = std::isfinite(landing) ? std::clamp(landing, first, last) : last;
    flight.partial =
        !(std::isfinite(takeoff) && takeoff > first) || !(std::isfinite(landing) && landing < last);
    if (!(flight.landing_s - flight.takeoff_s >= options.min_flight_s)) continue;
    flight.takeoff_frame = FirstFrameAtOrAfter(time_s, flight.takeoff_s);
    flight.landing_frame = FirstFrameAtOrAfter(time_s, flight.landing_s);
    if (com_z_m.size() > 0) FitFlightParabola(time_s, com_z_m, &flight);
    result.flights.push_back(flight);
  }
  std::sort(result.flights.begin(), result.flights.end(), [](const Flight& x, const Flight& y) {
    return x.takeoff_s < y.takeoff_s;
  });
  return result;
}

PhaseSegmentation DetectFlightsFromFeet(const Eigen::VectorXd& time_s,
                                        const Eigen::VectorXd& feet_z_m,
                                        double surface_z_m,
                                        const Eigen::VectorXd& com_z_m,
                                        const PhaseOptions& options) {
  DemandValidOptions(options, "phase options");
  ACRO_DEMAND(time_s.size() == feet_z_m.size() &&
              (com_z_m.size() == feet_z_m.size() || com_z_m.size() == 0));
  // In the air while the lowest sole is above the surface: the signal −z is at most −surface.
  PhaseSegmentation result = FlightsBelowThreshold(time_s,
                                                   -feet_z_m,
                                                   -(surface_z_m + options.feet_clearance_m),
                                                   options.feet_bridge_s,
                                                   time_s,
                                                   com_z_m,
                                                   options);
  result.method = "feet";
  return result;
}

std::string SurfaceEstimate::Describe() const {
  const int n = static_cast<int>(contact_z_m.size());
  return fmt::format("{} at rest {:.3f} m (spread {:.3f} m over {} contact{}{})",
                     gives_way ? "bed" : "floor",
                     z_m,
                     spread_m,
                     n,
                     n == 1 ? "" : "s",
                     gives_way ? fmt::format(", soles sink {:.2f} m", depth_m) : "");
}

namespace {

double Median(std::vector<double> v) {
  if (v.empty()) return std::numeric_limits<double>::quiet_NaN();
  const size_t m = v.size() / 2;
  std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(m), v.end());
  const double hi = v[m];
  if (v.size() % 2 == 1) return hi;
  return 0.5 * (hi + *std::max_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(m)));
}

// Linear interpolation of uniformly sampled values at time t.
double Interpolate(const Eigen::VectorXd& time_s, const Eigen::VectorXd& values, double t) {
  const int n = static_cast<int>(time_s.size());
  const double dt = (time_s[n - 1] - time_s[0]) / (n - 1);
  const double u = std::clamp((t - time_s[0]) / dt, 0.0, n - 1.0);
  const int i = std::min(static_cast<int>(u), n - 2);
  return values[i] + (u - i) * (values[i + 1] - values[i]);
}

// The COM's height in a contact: z_eq + c1 cos ω(t − t_ref) + c2 sin ω(t − t_ref), c = (z_eq, c1,
// c2).
struct ContactSinusoid {
  Eigen::Vector3d c = Eigen::Vector3d::Zero();
  double t_ref = 0, omega = 0;
};

// The COM in a contact of a sprung bed: z = z_eq + c1 cos ω(t − t_ref) + c2 sin ω(t − t_ref) over
// [first, last], ω scanned from 4 to 40 rad/s (bed periods 0.16–1.6 s), each ω one linear solve.
ContactSinusoid FitContactSinusoid(const Eigen::VectorXd& t,
                                   const Eigen::VectorXd& z,
                                   int first,
                                   int last) {
  ContactSinusoid best;
  best.t_ref = t[(first + last) / 2];
  double best_sse = std::numeric_limits<double>::infinity();
  const int rows = last - first + 1;
  Eigen::MatrixXd A(rows, 3);
  Eigen::VectorXd b = z.segment(first, rows);
  for (double omega = 4.0; omega <= 40.0; omega += 0.05) {
    for (int i = 0; i < rows; ++i) {
      const double tau = t[first + i] - best.t_ref;
      A.row(i) << 1.0, std::cos(omega * tau), std::sin(omega * tau);
    }
    const Eigen::Vector3d c = A.colPivHouseholderQr().solve(b);
    const double sse = (A * c - b).squaredNorm();
    if (sse < best_sse) {
      best_sse = sse;
      best.c = c;
      best.omega = omega;
    }
  }
  return best;
}

}  // namespace

std::optional<SurfaceEstimate> EstimateContactSurface(const Eigen::VectorXd& time_s,
                                                      const Eigen::VectorXd& feet_z_m,
                                                      const Eigen::VectorXd& com_z_m,
                                                      const PhaseSegmentation& com_phases,
                                                      const PhaseOptions& options) {
  DemandValidOptions(options, "phase options");
  ACRO_DEMAND(time_s.size() == feet_z_m.size() && time_s.size() == com_z_m.size());
  const int n = static_cast<int>(time_s.size());
  const std::vector<Flight>& flights = com_phases.flights;
  if (n < 16 || flights.empty() || !feet_z_m.allFinite() || !com_z_m.allFinite())
    return std::nullopt;
  const double dt = (time_s[n - 1] - time_s[0]) / (n - 1);
  const double g = options.gravity_m_per_s2;
  // The support per unit mass, a + g, lightly smoothed: only used to find where it pushes hard.
  const int h = std::max(2, static_cast<int>(std::lround(0.025 / dt)));
  const Eigen::VectorXd support = SavitzkyGolaySecondDerivative(com_z_m, dt, h).array() + g;

  // The core: where the support exceeds one body weight (the bed below its sag point), wide enough
  // to reach towards the rest level (a real bed stiffens as it sinks), narrow enough to leave out
  // the force's onset the marker filter smears.
  constexpr double kCoreSupport = 1.0;
  SurfaceEstimate out;
  std::vector<double> depths;
  int floors = 0;
  // Contacts: before each flight (after the previous one, or from the recording's start).
  for (size_t k = 0; k <= flights.size(); ++k) {
    const int from = k == 0 ? 0 : flights[k - 1].landing_frame;
    const int to = k == flights.size() ? n - 1 : flights[k].takeoff_frame - 1;
    if (to - from < 4) continue;
    // The contact's core: the run around its hardest push where the support exceeds kCoreSupport g
    // (short dips bridged), which must lie inside the recording.
    int peak = from;
    for (int i = from; i <= to; ++i)
      if (support[i] > support[peak]) peak = i;
    if (support[peak] < kCoreSupport * g) continue;
    int first = peak, last = peak;
    auto pushing = [&](int i) { return i >= from && i <= to && support[i] > kCoreSupport * g; };
    while (pushing(first - 1) || pushing(first - 2)) first -= pushing(first - 1) ? 1 : 2;
    while (pushing(last + 1) || pushing(last + 2)) last += pushing(last + 1) ? 1 : 2;
    if (first <= 0 || last >= n - 1 || last - first < 5) continue;
    double low = feet_z_m[first], high = feet_z_m[first];
    for (int i = first; i <= last; ++i) {
      low = std::min(low, feet_z_m[i]);
      high = std::max(high, feet_z_m[i]);
    }
    if (high - low < 0.06) {
      // A floor: the soles stay put while it pushes.
      std::vector<double> soles(feet_z_m.data() + first, feet_z_m.data() + last + 1);
      out.contact_z_m.push_back(Median(std::move(soles)));
      depths.push_back(0.0);
      ++floors;
      continue;
    }
    // A bed: its force per unit mass is ω² d (d the depression below rest), so the COM's
    // sinusoid accelerates at −g, as in flight, where the feet are at the bed's rest level: the
    // sinusoid z_eq + R cos θ at R cos θ = g / ω², before (landing) and after (take-off) its
    // bottom θ = π. The soles at those instants.
    const ContactSinusoid spring = FitContactSinusoid(time_s, com_z_m, first, last);
    if (spring.omega <= 4.0 || spring.omega >= 40.0) continue;  // no spring in the scanned range
    const double R = std::hypot(spring.c[1], spring.c[2]);
    const double ratio = g / (spring.omega * spring.omega * R);
    if (!(ratio < 1.0)) continue;
    const double phi = std::atan2(spring.c[2], spring.c[1]);  // θ = ω (t − t_ref) − φ
    // The bottom nearest the core's middle, then the rest level on either side of it.
    const double t_mid = 0.5 * (time_s[first] + time_s[last]);
    const double theta_mid = spring.omega * (t_mid - spring.t_ref) - phi;
    const double bottom =
        std::numbers::pi +
        2 * std::numbers::pi * std::round((theta_mid - std::numbers::pi) / (2 * std::numbers::pi));
    const double half = std::numbers::pi - std::acos(ratio);
    std::vector<double> levels;
    for (const double theta : {bottom - half, bottom + half}) {
      const double t = spring.t_ref + (theta + phi) / spring.omega;
      if (t > time_s[0] && t < time_s[n - 1]) levels.push_back(Interpolate(time_s, feet_z_m, t));
    }
    if (levels.empty()) continue;
    const double level = Median(levels);
    out.contact_z_m.push_back(level);
    depths.push_back(level - low);
  }
  if (out.contact_z_m.empty()) return std::nullopt;
  out.z_m = Median(out.contact_z_m);
  std::vector<double> deviations;
  for (double z : out.contact_z_m) deviations.push_back(std::abs(z - out.z_m));
  out.spread_m = 1.4826 * Median(deviations);
  out.depth_m = Median(depths);
  out.gives_way = 2 * floors < static_cast<int>(out.contact_z_m.size());
  return out;
}

}  // namespace acro::analysis
