// Zero-lag Butterworth: unit DC gain, −3 dB at the cutoff after the double pass (Winter's
// correction), no phase lag, and residual analysis choosing a cutoff between signal and noise.
#include "acro/reconstruct/butterworth.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>

namespace acro::analysis {
namespace {

/// Amplitude of a filtered sine (fitted over the middle half, away from the padded ends).
double Gain(int order, double fc, double f, double rate) {
  const int n = 4000;
  Eigen::VectorXd x(n);
  for (int i = 0; i < n; ++i) x[i] = std::sin(2 * std::numbers::pi * f * i / rate);
  ButterworthFilter(order, fc, rate).FilterZeroLag(x);
  double s = 0, c = 0;
  for (int i = n / 4; i < 3 * n / 4; ++i) {
    s += x[i] * std::sin(2 * std::numbers::pi * f * i / rate);
    c += x[i] * std::cos(2 * std::numbers::pi * f * i / rate);
  }
  // In phase (no lag): the cosine part vanishes.
  EXPECT_NEAR(c / (n / 4), 0.0, 2e-3) << "phase lag at " << f << " Hz";
  return s / (n / 4);
}

TEST(Butterworth, DcGainCutoffAndNoLag) {
  for (int order : {2, 3, 4}) {
    Eigen::VectorXd dc = Eigen::VectorXd::Constant(300, 2.5);
    ButterworthFilter(order, 6.0, 100.0).FilterZeroLag(dc);
    EXPECT_NEAR((dc.array() - 2.5).abs().maxCoeff(), 0.0, 1e-12);
    // −3 dB at fc for the forward-backward pair; the passband kept, the stopband removed.
    EXPECT_NEAR(Gain(order, 6.0, 6.0, 100.0), 1.0 / std::sqrt(2.0), 0.01) << order;
    EXPECT_NEAR(Gain(order, 6.0, 1.0, 100.0), 1.0, 0.01) << order;
    EXPECT_LT(Gain(order, 6.0, 30.0, 100.0), 0.02) << order;
  }
}

TEST(Butterworth, ResidualAnalysisChoosesBetweenSignalAndNoise) {
  // 2 Hz and 4 Hz content plus 2 mm white noise at 200 Hz.
  std::mt19937 rng(5);
  std::normal_distribution<double> noise(0, 2e-3);
  Eigen::MatrixXd x(1000, 3);
  for (int i = 0; i < 1000; ++i)
    for (int c = 0; c < 3; ++c)
      x(i, c) = 0.3 * std::sin(2 * std::numbers::pi * 2.0 * i / 200.0 + c) +
                0.05 * std::sin(2 * std::numbers::pi * 4.0 * i / 200.0) + noise(rng);
  x(100, 1) = std::nan("");  // a gap splits one signal into runs
  const ResidualAnalysis r = CalcResidualAnalysis(x, 200.0, 2);
  EXPECT_GT(r.chosen_cutoff_hz, 4.0);
  EXPECT_LT(r.chosen_cutoff_hz, 20.0);
  // The noise intercept estimates the noise level (2 mm) within a factor of 1.5.
  EXPECT_GT(r.noise_intercept, 2e-3 / 1.5);
  EXPECT_LT(r.noise_intercept, 2e-3 * 1.5);
}

}  // namespace
}  // namespace acro::analysis
