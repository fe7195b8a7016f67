#include "acro/pose/left_right.h"

#include <algorithm>
#include <array>
#include <limits>

#include <fmt/format.h>

#include "acro/pose/keypoints.h"

namespace acro::pose {
namespace {

constexpr int kStates = 4;  // bit 0: legs exchanged, bit 1: arms and face exchanged

bool InLegs(int left) { return left >= 23; }
bool Exchanged(int state, int left) { return (state & (InLegs(left) ? 1 : 2)) != 0; }

// A keypoint's position under a labelling: where `state` puts landmark k.
Eigen::Vector2d At(const capture::DetectedPerson& k, int state, int index, const std::vector<int>& partner) {
  const int p = partner[index];
  const int source = (p >= 0 && Exchanged(state, std::min(index, p))) ? p : index;
  return k.block<2, 1>(0, source);
}

double TorsoLength(const capture::DetectedPerson& k) {
  return ((k.block<2, 1>(0, 11) + k.block<2, 1>(0, 12)) - (k.block<2, 1>(0, 23) + k.block<2, 1>(0, 24))).norm() / 2;
}

}  // namespace

bool LeftRightOptions::IsValid(std::string* why) const {
  if (!(exchange_cost >= 0 && exchange_cost < 1)) {
    if (why) *why = fmt::format("exchange_cost {} not in [0, 1)", exchange_cost);
    return false;
  }
  return true;
}

int RepairLeftRight(std::vector<FramePose>* frames, const LeftRightOptions& options) {
  // Each landmark's partner on the other side (−1 for the nose).
  std::vector<int> partner(33, -1);
  std::vector<int> paired;
  for (const auto& [l, r] : BlazePoseLeftRightPairs()) {
    partner[l] = r;
    partner[r] = l;
    paired.push_back(l);
    paired.push_back(r);
  }
  int changed = 0;
  std::size_t begin = 0;
  while (begin < frames->size()) {
    if (!(*frames)[begin].found) {
      ++begin;
      continue;
    }
    std::size_t end = begin;
    while (end < frames->size() && (*frames)[end].found) ++end;
    // Viterbi over the chain [begin, end).
    const std::size_t n = end - begin;
    std::vector<std::array<double, kStates>> cost(n);
    std::vector<std::array<int, kStates>> from(n);
    const auto exchange_cost = [&](int state) {
      return options.exchange_cost * ((state & 1) + ((state >> 1) & 1));
    };
    for (int s = 0; s < kStates; ++s) cost[0][s] = exchange_cost(s);
    for (std::size_t t = 1; t < n; ++t) {
      const capture::DetectedPerson& a = (*frames)[begin + t - 1].keypoints;
      const capture::DetectedPerson& b = (*frames)[begin + t].keypoints;
      const double scale = std::max(TorsoLength(a), 1.0) * static_cast<double>(paired.size());
      for (int s = 0; s < kStates; ++s) {
        cost[t][s] = std::numeric_limits<double>::infinity();
        for (int p = 0; p < kStates; ++p) {
          double move = 0.0;
          for (int k : paired) move += (At(b, s, k, partner) - At(a, p, k, partner)).norm();
          const double c = cost[t - 1][p] + move / scale + exchange_cost(s);
          if (c < cost[t][s]) {
            cost[t][s] = c;
            from[t][s] = p;
          }
        }
      }
    }
    int state = static_cast<int>(std::min_element(cost[n - 1].begin(), cost[n - 1].end()) - cost[n - 1].begin());
    for (std::size_t t = n; t-- > 0;) {
      FramePose& f = (*frames)[begin + t];
      if (state != 0) {
        for (int k : paired)
          if (k < partner[k] && Exchanged(state, k)) f.keypoints.col(k).swap(f.keypoints.col(partner[k]));
        f.swapped_groups ^= state;
        ++changed;
      }
      if (t > 0) state = from[t][state];
    }
    begin = end;
  }
  return changed;
}

}  // namespace acro::pose
