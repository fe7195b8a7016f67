#include "acro/reconstruct/gap_filling.h"

#include <cmath>

#include <Eigen/Geometry>

#include "acro/base/cubic_spline.h"
#include "acro/base/demand.h"

namespace acro::analysis {

namespace {

bool Valid(const Eigen::Matrix3Xd& p, int frame, int marker, int M) {
  return !std::isnan(p(0, Eigen::Index(frame) * M + marker));
}

/// A frame from three points: origin a, x along b − a, z normal to the plane (a, b, c).
bool TriadFrame(const Eigen::Vector3d& a,
                const Eigen::Vector3d& b,
                const Eigen::Vector3d& c,
                Eigen::Matrix3d* R) {
  const Eigen::Vector3d x = b - a;
  const Eigen::Vector3d zz = x.cross(c - a);
  if (x.norm() < 1e-6 || zz.norm() < 1e-9) return false;
  R->col(0) = x.normalized();
  R->col(2) = zz.normalized();
  R->col(1) = R->col(2).cross(R->col(0));
  return true;
}

}  // namespace

bool GapFillingOptions::IsValid(std::string* why) const {
  if (max_spline_gap_frames < 0 || spline_support_frames < 1 || !(max_rigid_gap_s >= 0)) {
    if (why) *why = "gap lengths must be non-negative and the spline support at least 1";
    return false;
  }
  return true;
}

std::string GapFillingSummary::BriefReport() const {
  return std::to_string(gaps_found) + " gaps: " + std::to_string(filled_spline) + " by spline, " +
         std::to_string(filled_rigid) + " rigid-body, " + std::to_string(left_open) +
         " left open; " + std::to_string(samples_filled) + " samples filled";
}

GapFillingSummary FillGaps(Eigen::Matrix3Xd& positions,
                           int M,
                           const std::vector<int>& segment_of_marker,
                           double rate_hz,
                           const GapFillingOptions& options) {
  ACRO_DEMAND(M > 0 && positions.cols() % M == 0);
  ACRO_DEMAND(static_cast<int>(segment_of_marker.size()) == M && rate_hz > 0);
  const int F = static_cast<int>(positions.cols() / M);
  const Eigen::Matrix3Xd original = positions;  // partners and splines use recorded samples only
  GapFillingSummary summary;
  const int max_rigid = static_cast<int>(std::floor(options.max_rigid_gap_s * rate_hz + 1e-9));
  for (int m = 0; m < M; ++m) {
    int f = 0;
    while (f < F) {
      if (Valid(original, f, m, M)) {
        ++f;
        continue;
      }
      int end = f;
      while (end < F && !Valid(original, end, m, M)) ++end;
      const int first = f, last = end - 1, len = end - f;
      f = end;
      // Leading or trailing gaps (and markers never seen) are not gaps but absences.
      if (first == 0 || end == F) continue;
      ++summary.gaps_found;
      if (len <= options.max_spline_gap_frames) {
        // Spline through up to `support` recorded samples on each side.
        std::vector<double> t;
        std::vector<std::vector<double>> y(3);
        std::vector<int> frames;
        for (int k = first - 1; k >= 0 && int(frames.size()) < options.spline_support_frames; --k)
          if (Valid(original, k, m, M)) frames.insert(frames.begin(), k);
        const size_t before = frames.size();
        for (int k = end; k < F && int(frames.size() - before) < options.spline_support_frames; ++k)
          if (Valid(original, k, m, M)) frames.push_back(k);
        for (int k : frames) {
          t.push_back(k);
          for (int d = 0; d < 3; ++d) y[size_t(d)].push_back(original(d, Eigen::Index(k) * M + m));
        }
        for (int d = 0; d < 3; ++d) {
          const CubicSpline<double> spline(t, y[size_t(d)]);
          for (int k = first; k <= last; ++k)
            positions(d, Eigen::Index(k) * M + m) = spline.Eval(double(k)).value;
        }
        ++summary.filled_spline;
        summary.samples_filled += len;
        continue;
      }
      // Rigid-body fill: three partners of the same segment present from first−1 to end.
      const int seg = segment_of_marker[size_t(m)];
      std::vector<int> partners;
      for (int o = 0; o < M && seg >= 0 && partners.size() < 3; ++o) {
        if (o == m || segment_of_marker[size_t(o)] != seg) continue;
        bool ok = true;
        for (int k = first - 1; k <= end && ok; ++k) ok = Valid(original, k, o, M);
        if (ok) partners.push_back(o);
      }
      Eigen::Matrix3d R0, R1;
      auto P = [&](int k, int o) -> Eigen::Vector3d {
        return original.col(Eigen::Index(k) * M + o);
      };
      if (len > max_rigid || partners.size() < 3 ||
          !TriadFrame(P(first - 1, partners[0]),
                      P(first - 1, partners[1]),
                      P(first - 1, partners[2]),
                      &R0) ||
          !TriadFrame(P(end, partners[0]), P(end, partners[1]), P(end, partners[2]), &R1)) {
        ++summary.left_open;
        continue;
      }
      // The marker in the partners' frame at both ends, blended linearly across the gap.
      const Eigen::Vector3d local0 = R0.transpose() * (P(first - 1, m) - P(first - 1, partners[0]));
      const Eigen::Vector3d local1 = R1.transpose() * (P(end, m) - P(end, partners[0]));
      bool ok = true;
      for (int k = first; k <= last && ok; ++k) {
        Eigen::Matrix3d R;
        ok = TriadFrame(P(k, partners[0]), P(k, partners[1]), P(k, partners[2]), &R);
        const double s = double(k - first + 1) / double(len + 1);
        if (ok)
          positions.col(Eigen::Index(k) * M + m) =
              P(k, partners[0]) + R * ((1 - s) * local0 + s * local1);
      }
      if (!ok) {
        for (int k = first; k <= last; ++k)
          positions.col(Eigen::Index(k) * M + m).setConstant(std::nan(""));
        ++summary.left_open;
        continue;
      }
      ++summary.filled_rigid;
      summary.samples_filled += len;
    }
  }
  return summary;
}

}  // namespace acro::analysis
