#include "acro/reconstruct/butterworth.h"

#include <algorithm>
#include <cmath>
#include <complex>
#include <numbers>
#include <thread>
#include <vector>

#include "acro/base/demand.h"

namespace acro::analysis {

ButterworthFilter::ButterworthFilter(int order, double cutoff_hz, double rate_hz)
    : order_(order), cutoff_hz_(cutoff_hz) {
  ACRO_DEMAND(order >= 1 && order <= 8);
  ACRO_DEMAND(rate_hz > 0 && cutoff_hz > 0);
  // Per-pass cutoff so that the forward-backward filter is −3 dB at fc (Winter 2009, §3.4.4.4).
  const double C = std::pow(std::sqrt(2.0) - 1.0, 1.0 / (2.0 * order));
  const double fc_pass = std::min(cutoff_hz / C, 0.49 * rate_hz);
  // Pre-warped analog cutoff (bilinear transform s = 2 fs (z − 1)/(z + 1)).
  const double K = std::tan(std::numbers::pi * fc_pass / rate_hz);
  // Analog prototype poles p_k = exp(iπ(2k + N − 1)/(2N)), k = 1..N; conjugate pairs → biquads
  // H(s) = 1/(s² − 2Re(p)s + 1) with s → (z − 1)/((z + 1)K); a real pole → a first-order section.
  for (int k = 1; k <= order / 2; ++k) {
    const double theta = std::numbers::pi * (2.0 * k + order - 1.0) / (2.0 * order);
    const double two_re = -2.0 * std::cos(theta);  // −2 Re(p) > 0
    const double a0 = 1.0 + two_re * K + K * K;
    Section s;
    s.b0 = K * K / a0;
    s.b1 = 2.0 * s.b0;
    s.b2 = s.b0;
    s.a1 = 2.0 * (K * K - 1.0) / a0;
    s.a2 = (1.0 - two_re * K + K * K) / a0;
    sections_.push_back(s);
  }
  if (order % 2 == 1) {
    // H(s) = 1/(s + 1): b = K/(1 + K) (1, 1), a1 = (K − 1)/(K + 1).
    Section s;
    s.b0 = K / (1.0 + K);
    s.b1 = s.b0;
    s.b2 = 0.0;
    s.a1 = (K - 1.0) / (K + 1.0);
    s.a2 = 0.0;
    sections_.push_back(s);
  }
}

void ButterworthFilter::FilterOnce(std::vector<double>& x) const {
  for (const Section& s : sections_) {
    // Direct form II transposed, started in the steady state of the first sample (unit DC gain).
    const double x0 = x.front();
    double z1 = x0 * (1.0 - s.b0);
    double z2 = x0 * (s.b2 - s.a2);
    for (double& v : x) {
      const double in = v;
      const double out = s.b0 * in + z1;
      z1 = s.b1 * in - s.a1 * out + z2;
      z2 = s.b2 * in - s.a2 * out;
      v = out;
    }
  }
}

void ButterworthFilter::FilterZeroLag(Eigen::Ref<Eigen::VectorXd> x) const {
  const Eigen::Index n = x.size();
  if (n < 3 * (order_ + 1)) return;
  // Odd reflection about the end samples (as MATLAB's filtfilt), pad = min(n − 1, 3·(order+1)·4).
  const Eigen::Index pad = std::min<Eigen::Index>(n - 1, 12 * (order_ + 1));
  std::vector<double> y(static_cast<size_t>(n + 2 * pad));
  for (Eigen::Index i = 0; i < pad; ++i) y[size_t(i)] = 2.0 * x[0] - x[pad - i];
  for (Eigen::Index i = 0; i < n; ++i) y[size_t(pad + i)] = x[i];
  for (Eigen::Index i = 0; i < pad; ++i) y[size_t(pad + n + i)] = 2.0 * x[n - 1] - x[n - 2 - i];
  FilterOnce(y);
  std::reverse(y.begin(), y.end());
  FilterOnce(y);
  std::reverse(y.begin(), y.end());
  for (Eigen::Index i = 0; i < n; ++i) x[i] = y[size_t(pad + i)];
}

void FilterWithGaps(const ButterworthFilter& filter, Eigen::Ref<Eigen::VectorXd> x) {
  Eigen::Index i = 0;
  const Eigen::Index n = x.size();
  while (i < n) {
    while (i < n && std::isnan(x[i])) ++i;
    Eigen::Index j = i;
    while (j < n && !std::isnan(x[j])) ++j;
    if (j > i) filter.FilterZeroLag(x.segment(i, j - i));
    i = j;
  }
}

void FilterColumnsWithGaps(const ButterworthFilter& filter, Eigen::MatrixXd& signals) {
  for (Eigen::Index c = 0; c < signals.cols(); ++c) FilterWithGaps(filter, signals.col(c));
}

ResidualAnalysis CalcResidualAnalysis(const Eigen::MatrixXd& signals,
                                      double rate_hz,
                                      int order,
                                      int num_threads) {
  ResidualAnalysis r;
  ACRO_DEMAND(std::isfinite(rate_hz) && rate_hz >= kMinResidualAnalysisRateHz);
  const double top = std::min(rate_hz / 4.0, kMaxResidualAnalysisCutoffHz);
  for (double fc = 1.0; fc <= top + 1e-9; fc += 0.5) r.cutoff_hz.push_back(fc);
  r.residual.assign(r.cutoff_hz.size(), 0.0);
  // R(fc) pooled over all valid samples of all signals; the cutoffs are independent, so workers
  // take every k-th one (each sum is formed in the same order whatever the number of workers).
  auto residual_at = [&](size_t k) {
    const ButterworthFilter filter(order, r.cutoff_hz[k], rate_hz);
    double sum = 0.0;
    long count = 0;
    Eigen::VectorXd x(signals.rows());
    for (Eigen::Index c = 0; c < signals.cols(); ++c) {
      x = signals.col(c);
      FilterWithGaps(filter, x);
      for (Eigen::Index i = 0; i < x.size(); ++i) {
        if (std::isnan(x[i])) continue;
        const double d = x[i] - signals(i, c);
        sum += d * d;
        ++count;
      }
    }
    r.residual[k] = count > 0 ? std::sqrt(sum / double(count)) : 0.0;
  };
  const int hw = std::max(1, static_cast<int>(std::thread::hardware_concurrency()));
  const int workers =
      std::clamp(num_threads > 0 ? num_threads : hw, 1, static_cast<int>(r.cutoff_hz.size()));
  std::vector<std::thread> pool;
  for (int w = 1; w < workers; ++w)
    pool.emplace_back([&, w] {
      for (size_t k = static_cast<size_t>(w); k < r.cutoff_hz.size(); k += size_t(workers))
        residual_at(k);
    });
  for (size_t k = 0; k < r.cutoff_hz.size(); k += size_t(workers)) residual_at(k);
  for (std::thread& t : pool) t.join();
  // Line through the upper half (least squares), its intercept a at fc = 0.
  const size_t start = r.cutoff_hz.size() / 2;
  double sx = 0, sy = 0, sxx = 0, sxy = 0;
  const double m = double(r.cutoff_hz.size() - start);
  for (size_t i = start; i < r.cutoff_hz.size(); ++i) {
    sx += r.cutoff_hz[i];
    sy += r.residual[i];
    sxx += r.cutoff_hz[i] * r.cutoff_hz[i];
    sxy += r.cutoff_hz[i] * r.residual[i];
  }
  const double slope = (m * sxy - sx * sy) / (m * sxx - sx * sx);
  r.noise_intercept = (sy - slope * sx) / m;
  r.chosen_cutoff_hz = r.cutoff_hz.back();
  for (size_t i = 0; i < r.cutoff_hz.size(); ++i) {
    if (r.residual[i] <= r.noise_intercept) {
      r.chosen_cutoff_hz = r.cutoff_hz[i];
      break;
    }
  }
  return r;
}

}  // namespace acro::analysis
