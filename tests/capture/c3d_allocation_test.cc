// "One pass, no per-sample allocation" (issue 2, capture benchmark goal): the number of heap
// allocations made by ReadC3dFromMemory does not depend on the number of frames. malloc is
// interposed (glibc) to count every allocation — operator new and Eigen's both go through it.

#include <atomic>
#include <cmath>
#include <cstdlib>

#include <gtest/gtest.h>

#include "acro/capture/c3d.h"

extern "C" void* __libc_malloc(std::size_t size);

namespace {
std::atomic<bool> g_counting{false};
std::atomic<long> g_allocations{0};
}  // namespace

extern "C" void* malloc(std::size_t size) {
  if (g_counting.load(std::memory_order_relaxed))
    g_allocations.fetch_add(1, std::memory_order_relaxed);
  return __libc_malloc(size);
}

namespace acro::capture {
namespace {

// 60 markers at 200 Hz, 16 analog channels at 2 kHz with a TYPE-2 plate on the first six, gaps.
std::vector<std::uint8_t> GeneratedFile(int frames) {
  Trial t;
  t.source.format = "generated";
  t.point_rate_hz = 200;
  t.num_frames = frames;
  for (int p = 0; p < 60; ++p)
    t.points.push_back({"M" + std::to_string(p), "", PointType::kMarker, "m"});
  t.positions.resize(3, std::int64_t(frames) * 60);
  for (Eigen::Index i = 0; i < t.positions.cols(); ++i)
    t.positions.col(i) << 0.001 * (i % 97), 1.0, 0.5;
  t.position(frames / 2, 7).setConstant(std::nan(""));
  t.analog_rate_hz = 2000;
  const char* units[6] = {"N", "N", "N", "Nmm", "Nmm", "Nmm"};
  for (int c = 0; c < 16; ++c)
    t.analog_channels.push_back(
        {"A" + std::to_string(c), "", c < 6 ? units[c] : "V", 1.0, 0.0, 0.0});
  t.analog = Eigen::MatrixXd::Constant(16, std::int64_t(frames) * 10, 1.0);
  t.analog.row(2).setConstant(-700.0);
  ForcePlate plate;
  plate.type = 2;
  plate.corners_W_m << 0.6, 0, 0, 0.6, 0, 0, 0.4, 0.4, 0, 0, 0, 0;
  plate.origin_F_m << 0, 0, -0.04;
  plate.channels = {0, 1, 2, 3, 4, 5};
  plate.zero = {0, 0};
  t.force_plates.push_back(plate);
  return WriteC3dToMemory(t);
}

long CountReadAllocations(const std::vector<std::uint8_t>& bytes) {
  g_allocations = 0;
  g_counting = true;
  {
    const Trial t = ReadC3dFromMemory(bytes, "generated.c3d");
    g_counting = false;
    EXPECT_EQ(t.force_plates.at(0).force_W_N.cols(), t.num_analog_samples());
  }
  return g_allocations.load();
}

TEST(C3dAllocation, ReadAllocationsDoNotGrowWithFrames) {
  const std::vector<std::uint8_t> short_file = GeneratedFile(100);
  const std::vector<std::uint8_t> long_file = GeneratedFile(2000);
  CountReadAllocations(short_file);  // warm any lazy one-time allocations
  const long short_count = CountReadAllocations(short_file);
  const long long_count = CountReadAllocations(long_file);
  EXPECT_GT(short_count, 0);  // the counter works
  EXPECT_EQ(short_count, long_count)
      << "100 frames: " << short_count << ", 2000 frames: " << long_count;
}

}  // namespace
}  // namespace acro::capture
