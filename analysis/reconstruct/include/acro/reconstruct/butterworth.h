#pragma once

// Zero-lag Butterworth low-pass filtering of marker trajectories and the choice of its cutoff by
// residual analysis (D. A. Winter, Biomechanics and Motor Control of Human Movement, 4th ed.,
// Wiley 2009, §3.4.4–3.4.5).

#include <string>
#include <vector>

#include <Eigen/Core>

namespace acro::analysis {

/// A digital Butterworth low-pass of order N as cascaded second-order sections (bilinear transform
/// with pre-warped cutoff), run forward and backward (zero phase). The cutoff given is that of the
/// whole forward-backward filter: each pass uses fc / C with C = (2^(1/2) − 1)^(1/(2N)) (Winter
/// 2009, eq. 3.36 generalised to order N), so that the double pass is −3 dB at fc.
class ButterworthFilter {
 public:
  ButterworthFilter(int order, double cutoff_hz, double rate_hz);
  /// Filters one run of samples (no NaN) in place; runs shorter than 3·(order + 1) samples are
  /// left as they are (too short to filter). The ends are padded by odd reflection.
  void FilterZeroLag(Eigen::Ref<Eigen::VectorXd> x) const;
  int order() const { return order_; }
  double cutoff_hz() const { return cutoff_hz_; }

 private:
  struct Section {
    double b0, b1, b2, a1, a2;
  };
  void FilterOnce(std::vector<double>& x) const;
  int order_;
  double cutoff_hz_;
  std::vector<Section> sections_;
};

/// Filters every coordinate of a signal with gaps: each run of non-NaN samples separately.
void FilterWithGaps(const ButterworthFilter& filter, Eigen::Ref<Eigen::VectorXd> x);

/// FilterWithGaps on every column of `signals` (one signal per column, one row per sample).
void FilterColumnsWithGaps(const ButterworthFilter& filter, Eigen::MatrixXd& signals);

struct ResidualAnalysis {
  std::vector<double> cutoff_hz;  ///< the cutoffs tried
  std::vector<double> residual;   ///< RMS difference raw − filtered at each cutoff (signal units)
  double noise_intercept = 0.0;   ///< intercept a of the line fitted to the noise-dominated tail
  double chosen_cutoff_hz = 0.0;  ///< where the residual falls to a (Winter's choice)
};

/// The residual analysis's scan: from 1 Hz to rate/4, at most kMaxResidualAnalysisCutoffHz (human
/// motion has nothing above 50 Hz; the scan's upper half, where only noise is removed, stays
/// wide, and a trial whose rate is 1 MHz costs no more than one at 1 kHz). Below
/// kMinResidualAnalysisRateHz (rate/4 = 2.5 Hz: four cutoffs) there is nothing to scan.
inline constexpr double kMaxResidualAnalysisCutoffHz = 250.0;
inline constexpr double kMinResidualAnalysisRateHz = 10.0;

/// Winter's residual analysis pooled over signals (columns of `signals`, NaN gaps allowed):
/// R(fc) = RMS(x − x̂_fc) for fc from 1 Hz to min(rate/4, 250 Hz) in 0.5 Hz steps; a straight
/// line fitted to
/// the upper half of that range (where only noise is removed) gives the intercept a at fc = 0;
/// the chosen cutoff is the lowest fc with R(fc) ≤ a. The cutoffs are shared out to `num_threads`
/// workers (0: the hardware's concurrency); the result does not depend on their number.
ResidualAnalysis CalcResidualAnalysis(const Eigen::MatrixXd& signals,
                                      double rate_hz,
                                      int order,
                                      int num_threads = 0);

}  // namespace acro::analysis
