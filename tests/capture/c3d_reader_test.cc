// C3D reader against the values other readers assert for the c3d.org and BTK suites
// (../shared/refdata/{c3dio-c3d_org_samples,BTKData}/expected.md). Coordinates in those tables are
// in the files' millimetres; the Trial holds metres, so they are compared after × 1000.

#include <cmath>
#include <cstring>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "acro/base/input_error.h"
#include "acro/capture/c3d.h"
#include "refdata.h"

namespace acro::capture {
namespace {

using acro::testing::RefdataFile;

constexpr char kOrg[] = "c3dio-c3d_org_samples/";

double Mm(const Trial& t, int frame, int point, int axis) {
  return t.position(frame, point)(axis) * 1000.0;
}

// ---------------------------------------------------------------------------------------------
// Sample 01: the same trial in Intel/DEC/MIPS × integer/float (BTK asserts the same values for
// all).
class Sample01 : public ::testing::TestWithParam<std::string> {};

TEST_P(Sample01, BtkValues) {
  const auto path = RefdataFile(std::string(kOrg) + "sample_01/" + GetParam());
  ACRO_REQUIRE_REFDATA_FILE(path);
  const Trial t = ReadC3d(path);
  EXPECT_EQ(t.point_rate_hz, 50);
  EXPECT_EQ(t.num_points(), 26);
  EXPECT_EQ(t.analog_rate_hz, 200);
  EXPECT_EQ(t.num_analog_channels(), 16);
  EXPECT_EQ(t.num_frames, 450);
  EXPECT_EQ(t.first_frame, 1);
  EXPECT_EQ(t.analog_samples_per_frame(), 4);
  EXPECT_EQ(t.points[0].label, "RFT1");
  EXPECT_NEAR(Mm(t, 8, 0, 0), 250.4166, 1e-4);
  EXPECT_NEAR(Mm(t, 16, 17, 0), 285.0, 1e-4);
  EXPECT_NEAR(Mm(t, 16, 17, 1), 222.4166, 1e-4);
  EXPECT_NEAR(Mm(t, 16, 17, 2), 564.4166, 1e-4);
  EXPECT_NEAR(t.residuals(0, 0), 1.3333, 1e-4);
  EXPECT_NEAR(t.residuals(14, 20), 1.91667, 1e-4);
  EXPECT_NEAR(t.analog(0, 0), -26.6599, 1e-3);
  EXPECT_NEAR(t.analog(0, 1), -25.8, 1e-4);
  ASSERT_EQ(t.events.size(), 3u);
  EXPECT_EQ(t.events[0].label, "RIC");
  EXPECT_NEAR(t.events[0].time_s, 2.72, 1e-4);
  EXPECT_EQ(t.events[1].label, "RHS");
  EXPECT_NEAR(t.events[1].time_s, 5.40, 1e-4);
  EXPECT_EQ(t.events[2].label, "RTO");
  EXPECT_NEAR(t.events[2].time_s, 7.32, 1e-4);
  EXPECT_EQ(t.source.point_units, "mm");
  EXPECT_EQ(t.source.point_units_to_m, 1e-3);
  EXPECT_EQ(t.source.max_interpolation_gap, 10);
  EXPECT_TRUE(t.warnings.empty()) << t.warnings.front();
}

INSTANTIATE_TEST_SUITE_P(AllSix,
                         Sample01,
                         ::testing::Values("Eb015pi.c3d",
                                           "Eb015pr.c3d",
                                           "Eb015si.c3d",
                                           "Eb015sr.c3d",
                                           "Eb015vi.c3d",
                                           "Eb015vr.c3d"));

TEST(C3dReader, Sample01ProcessorsAndStorage) {
  const std::vector<std::tuple<std::string, std::string, std::string>> cases = {
      {"Eb015pi.c3d", "Intel", "integer"},
      {"Eb015pr.c3d", "Intel", "float"},
      {"Eb015si.c3d", "MIPS", "integer"},
      {"Eb015sr.c3d", "MIPS", "float"},
      {"Eb015vi.c3d", "DEC", "integer"},
      {"Eb015vr.c3d", "DEC", "float"}};
  for (const auto& [file, processor, storage] : cases) {
    const auto path = RefdataFile(std::string(kOrg) + "sample_01/" + file);
    ACRO_REQUIRE_REFDATA_FILE(path);
    const Trial t = ReadC3d(path);
    EXPECT_EQ(t.source.processor, processor) << file;
    EXPECT_EQ(t.source.point_storage, storage) << file;
    EXPECT_EQ(t.source.format, "C3D");
  }
}

TEST(C3dReader, Eb015piDescriptionsAndScale) {
  const auto path = RefdataFile(std::string(kOrg) + "sample_01/Eb015pi.c3d");
  ACRO_REQUIRE_REFDATA_FILE(path);
  const Trial t = ReadC3d(path);
  EXPECT_EQ(t.points[9].description, "DISTAL FOOT");
  EXPECT_EQ(t.analog_channels[15].label, "CH16");
  EXPECT_EQ(t.analog_channels[2].description, "FORCE Z-COMP 1");
  EXPECT_NEAR(t.source.point_scale, 0.08333, 1e-4);
}

// The six variants give the same trajectories within one scale step (py-c3d's criterion: valid
// masks identical, |Δ| ≤ 1.01·|POINT:SCALE|), and the same analog samples.
TEST(C3dReader, Sample01VariantsAgree) {
  const std::vector<std::string> files = {
      "Eb015pi.c3d", "Eb015pr.c3d", "Eb015si.c3d", "Eb015sr.c3d", "Eb015vi.c3d", "Eb015vr.c3d"};
  const auto ref_path = RefdataFile(std::string(kOrg) + "sample_01/Eb015pr.c3d");
  ACRO_REQUIRE_REFDATA_FILE(ref_path);
  const Trial ref = ReadC3d(ref_path);
  const double step_m = 1.01 * std::abs(ref.source.point_scale) * 1e-3;
  for (const std::string& file : files) {
    const Trial t = ReadC3d(RefdataFile(std::string(kOrg) + "sample_01/" + file));
    ASSERT_EQ(t.positions.cols(), ref.positions.cols()) << file;
    double worst = 0;
    for (Eigen::Index i = 0; i < t.positions.cols(); ++i) {
      ASSERT_EQ(std::isnan(t.positions(0, i)), std::isnan(ref.positions(0, i)))
          << file << " sample " << i;
      if (!std::isnan(t.positions(0, i)))
        worst = std::max(worst, (t.positions.col(i) - ref.positions.col(i)).cwiseAbs().maxCoeff());
    }
    EXPECT_LE(worst, step_m) << file;
    ASSERT_EQ(t.analog.cols(), ref.analog.cols());
    // Analog samples: numpy isclose defaults (rtol 1e-5, atol 1e-8), as py-c3d.
    for (Eigen::Index i = 0; i < t.analog.size(); ++i) {
      ASSERT_LE(std::abs(t.analog.data()[i] - ref.analog.data()[i]),
                1e-8 + 1e-5 * std::abs(ref.analog.data()[i]))
          << file << " analog value " << i;
    }
    EXPECT_TRUE((t.residuals == ref.residuals).all()) << file;
    EXPECT_TRUE((t.camera_masks == ref.camera_masks).all()) << file;
    EXPECT_EQ(std::abs(t.source.point_scale), std::abs(ref.source.point_scale)) << file;
    EXPECT_EQ(t.source.max_interpolation_gap, ref.source.max_interpolation_gap) << file;
  }
}

// ---------------------------------------------------------------------------------------------
// Sample 02 (Vicon 370): BTK's values; the Intel/SGI integer files differ by one scale step in y.
TEST(C3dReader, Sample02BtkValues) {
  struct Case {
    const char* file;
    double y;
  };
  const Case cases[] = {{"dec_int.c3d", 523.8418},
                        {"dec_real.c3d", 523.8417},
                        {"pc_real.c3d", 523.8417},
                        {"sgi_real.c3d", 523.8417},
                        {"pc_int.c3d", 523.5606},
                        {"sgi_int.c3d", 523.5606}};
  for (const Case& c : cases) {
    const auto path = RefdataFile(std::string(kOrg) + "sample_02/" + c.file);
    ACRO_REQUIRE_REFDATA_FILE(path);
    const Trial t = ReadC3d(path);
    EXPECT_EQ(t.point_rate_hz, 50) << c.file;
    EXPECT_EQ(t.num_points(), 36) << c.file;
    EXPECT_EQ(t.num_frames, 89) << c.file;
    EXPECT_EQ(t.analog_rate_hz, 200) << c.file;
    EXPECT_EQ(t.num_analog_channels(), 16) << c.file;
    EXPECT_EQ(t.num_analog_samples(), 356) << c.file;
    EXPECT_EQ(t.points[3].label, "RSK1") << c.file;
    EXPECT_NEAR(Mm(t, 16, 3, 0), 384.0944, 1e-4) << c.file;
    EXPECT_NEAR(Mm(t, 16, 3, 1), c.y, 1e-4) << c.file;
    EXPECT_NEAR(Mm(t, 16, 3, 2), 311.2683, 1e-4) << c.file;
    EXPECT_EQ(t.analog_channels[2].label, "FZ1") << c.file;
    EXPECT_NEAR(t.analog(2, 15), 8.9280, 1e-4) << c.file;
    EXPECT_NEAR(t.analog(2, 39), 5.952, 1e-4) << c.file;
  }
}

TEST(C3dReader, Sample02VariantsAgreeWithinOneScaleStep) {
  const auto ref_path = RefdataFile(std::string(kOrg) + "sample_02/pc_real.c3d");
  ACRO_REQUIRE_REFDATA_FILE(ref_path);
  const Trial ref = ReadC3d(ref_path);
  const double step_m = 1.01 * std::abs(ref.source.point_scale) * 1e-3;
  for (const char* file :
       {"dec_int.c3d", "dec_real.c3d", "pc_int.c3d", "sgi_int.c3d", "sgi_real.c3d"}) {
    const Trial t = ReadC3d(RefdataFile(std::string(kOrg) + "sample_02/" + file));
    ASSERT_EQ(t.positions.cols(), ref.positions.cols()) << file;
    double worst = 0;
    for (Eigen::Index i = 0; i < t.positions.cols(); ++i) {
      ASSERT_EQ(std::isnan(t.positions(0, i)), std::isnan(ref.positions(0, i)))
          << file << " sample " << i;
      if (!std::isnan(t.positions(0, i)))
        worst = std::max(worst, (t.positions.col(i) - ref.positions.col(i)).cwiseAbs().maxCoeff());
    }
    EXPECT_LE(worst, step_m) << file;
    // py-c3d's other criteria: residuals equal, camera masks equal or off by at most 1 (dec_int),
    // |POINT:SCALE| equal, up to 2 header events unmatched (dec_int has 8, the others 9).
    EXPECT_TRUE((t.residuals == ref.residuals).all()) << file;
    EXPECT_LE((t.camera_masks.cast<int>() - ref.camera_masks.cast<int>()).abs().maxCoeff(), 1)
        << file;
    EXPECT_EQ(std::abs(t.source.point_scale), std::abs(ref.source.point_scale)) << file;
    int unmatched = 0;
    for (const Event& e : ref.events) {
      bool found = false;
      for (const Event& o : t.events) {
        found = found || (o.label == e.label && std::abs(o.time_s - e.time_s) <= 1e-7 &&
                          o.displayed == e.displayed);
      }
      unmatched += found ? 0 : 1;
    }
    EXPECT_LE(unmatched, 2) << file;
  }
}

// ---------------------------------------------------------------------------------------------
// A small file built byte by byte from the C3D manual, in each processor format, integer storage,
// unsigned analog: decoding must not depend on the reference files.
class C3dBytes {
 public:
  explicit C3dBytes(std::uint8_t processor) : processor_(processor) {}
  std::vector<std::uint8_t>& bytes() { return out_; }
  void U8(std::uint8_t v) { out_.push_back(v); }
  void U16(std::uint16_t v) {
    if (processor_ == 86) {
      out_.push_back(static_cast<std::uint8_t>(v >> 8));
      out_.push_back(static_cast<std::uint8_t>(v & 0xFF));
    } else {
      out_.push_back(static_cast<std::uint8_t>(v & 0xFF));
      out_.push_back(static_cast<std::uint8_t>(v >> 8));
    }
  }
  void I16(std::int16_t v) { U16(static_cast<std::uint16_t>(v)); }
  void F32(float f) {
    std::uint32_t bits;
    if (processor_ == 85) {
      // VAX F-float: value × 4 in IEEE bits, 16-bit halves swapped (C3D manual, "DEC floating
      // point").
      const float quad = f * 4.0f;
      std::memcpy(&bits, &quad, 4);
      if (f == 0.0f) bits = 0;
      out_.push_back(static_cast<std::uint8_t>((bits >> 16) & 0xFF));
      out_.push_back(static_cast<std::uint8_t>(bits >> 24));
      out_.push_back(static_cast<std::uint8_t>(bits & 0xFF));
      out_.push_back(static_cast<std::uint8_t>((bits >> 8) & 0xFF));
      return;
    }
    std::memcpy(&bits, &f, 4);
    for (int k = 0; k < 4; ++k) {
      const int shift = processor_ == 86 ? 24 - 8 * k : 8 * k;
      out_.push_back(static_cast<std::uint8_t>((bits >> shift) & 0xFF));
    }
  }
  void PutU16At(std::size_t at, std::uint16_t v) {
    if (processor_ == 86) {
      out_[at] = static_cast<std::uint8_t>(v >> 8);
      out_[at + 1] = static_cast<std::uint8_t>(v & 0xFF);
    } else {
      out_[at] = static_cast<std::uint8_t>(v & 0xFF);
      out_[at + 1] = static_cast<std::uint8_t>(v >> 8);
    }
  }
  // A record: name length (negative = locked), group id (negative for a group), name, offset to the
  // next record; `body` writes the rest.
  template <class Body>
  void Record(const std::string& name, int group_id, bool locked, Body body) {
    U8(static_cast<std::uint8_t>(
        static_cast<std::int8_t>(locked ? -int(name.size()) : int(name.size()))));
    U8(static_cast<std::uint8_t>(static_cast<std::int8_t>(group_id)));
    out_.insert(out_.end(), name.begin(), name.end());
    const std::size_t offset_at = out_.size();
    U16(0);
    body();
    PutU16At(offset_at, static_cast<std::uint16_t>(out_.size() - offset_at));
  }
  void Description(const std::string& d) {
    U8(static_cast<std::uint8_t>(d.size()));
    out_.insert(out_.end(), d.begin(), d.end());
  }
  void Chars(const std::string& text, std::vector<std::uint8_t> dims) {
    U8(0xFF);  // type −1
    U8(static_cast<std::uint8_t>(dims.size()));
    out_.insert(out_.end(), dims.begin(), dims.end());
    out_.insert(out_.end(), text.begin(), text.end());
  }

 private:
  std::uint8_t processor_;
  std::vector<std::uint8_t> out_;
};

std::vector<std::uint8_t> SyntheticFile(std::uint8_t processor) {
  C3dBytes b(processor);
  // Header (block 1): parameters at block 2, 2 points, 2 channels × 2 samples, frames 5..7.
  b.U8(2);
  b.U8(0x50);
  b.U16(2);       // points
  b.U16(4);       // analog words per frame
  b.U16(5);       // first frame
  b.U16(7);       // last frame
  b.U16(10);      // max gap
  b.F32(0.5f);    // scale (integer storage)
  b.U16(4);       // data start block
  b.U16(2);       // analog samples per frame
  b.F32(100.0f);  // frame rate
  b.bytes().resize(298, 0);
  b.U16(12345);
  b.U16(2);  // events
  b.bytes().resize(304, 0);
  b.F32(0.25f);
  b.F32(1.5f);
  b.bytes().resize(376, 0);
  b.U8(1);
  b.U8(0);
  b.bytes().resize(396, 0);
  for (char c : std::string("HS  TO  ")) b.U8(static_cast<std::uint8_t>(c));
  b.bytes().resize(512, 0);
  // Parameter section (blocks 2–3).
  b.U8(1);
  b.U8(0x50);
  b.U8(2);
  b.U8(processor);
  // A parameter before its group, locked.
  b.Record("USED", 1, true, [&] {
    b.U8(2);
    b.U8(0);
    b.I16(2);
    b.Description("number of points");
  });
  b.Record("POINT", -1, false, [&] { b.Description("3D points"); });
  b.Record("ANALOG", -2, true, [&] { b.Description(""); });
  b.Record("SCALE", 1, false, [&] {
    b.U8(4);
    b.U8(0);
    b.F32(0.5f);
    b.Description("");
  });
  b.Record("RATE", 1, false, [&] {
    b.U8(4);
    b.U8(0);
    b.F32(100.0f);
    b.Description("");
  });
  b.Record("LABELS", 1, false, [&] {
    b.Chars("TOE HEEL", {4, 2});
    b.Description("");
  });
  b.Record("UNITS", 1, false, [&] {
    b.Chars("mm", {2});
    b.Description("");
  });
  b.Record("USED", 2, false, [&] {
    b.U8(2);
    b.U8(0);
    b.I16(2);
    b.Description("");
  });
  b.Record("LABELS", 2, false, [&] {
    b.Chars("EMG1EMG2", {4, 2});
    b.Description("");
  });
  b.Record("FORMAT", 2, false, [&] {
    b.Chars("UNSIGNED", {8});
    b.Description("");
  });
  b.Record("BITS", 2, false, [&] {
    b.U8(2);
    b.U8(0);
    b.I16(16);
    b.Description("");
  });
  b.Record("SCALE", 2, false, [&] {
    b.U8(4);
    b.U8(1);
    b.U8(2);
    b.F32(0.01f);
    b.F32(-0.5f);
    b.Description("");
  });
  b.Record("OFFSET", 2, false, [&] {
    b.U8(2);
    b.U8(1);
    b.U8(2);
    b.I16(-32768);  // 32768 read unsigned
    b.I16(2048);
    b.Description("");
  });
  b.Record("GEN_SCALE", 2, false, [&] {
    b.U8(4);
    b.U8(0);
    b.F32(2.0f);
    b.Description("");
  });
  b.Record("RATE", 2, false, [&] {
    b.U8(4);
    b.U8(0);
    b.F32(200.0f);
    b.Description("");
  });
  b.U8(0);  // end of the parameter section
  b.bytes().resize(3 * 512, 0);
  // Data (block 4): per frame 2 points × (x, y, z, residual word), then 2 samples × 2 channels.
  for (int f = 0; f < 3; ++f) {
    b.I16(static_cast<std::int16_t>(100 + f));
    b.I16(-200);
    b.I16(300);
    b.I16(static_cast<std::int16_t>((3 << 8) | 10));  // camera mask 3, residual 10 × 0.5
    b.I16(static_cast<std::int16_t>(-400 - f));
    b.I16(500);
    b.I16(600);
    b.I16(f == 1 ? -1 : 0);  // invalid at the second frame
    for (int s = 0; s < 2; ++s) {
      b.U16(static_cast<std::uint16_t>(40000 + 10 * f + s));
      b.U16(static_cast<std::uint16_t>(1000));
    }
  }
  return b.bytes();
}

// Header word 10 (analog samples per frame) left at 0 by a writer: recovered from word 3 and
// ANALOG:USED, with a warning.
TEST(C3dReader, MissingHeaderSamplesPerFrame) {
  std::vector<std::uint8_t> bytes = SyntheticFile(84);
  const Trial reference = ReadC3dFromMemory(bytes, "synthetic.c3d");
  bytes[18] = 0;
  bytes[19] = 0;
  const Trial t = ReadC3dFromMemory(bytes, "synthetic.c3d");
  EXPECT_EQ(t.analog_samples_per_frame(), 2);
  EXPECT_TRUE(t.analog == reference.analog);
  EXPECT_TRUE(t.positions.cwiseEqual(reference.positions).count() +
                  reference.positions.array().isNaN().count() ==
              reference.positions.size());
  ASSERT_EQ(t.warnings.size(), 1u);
  EXPECT_NE(t.warnings[0].find("byte 18"), std::string::npos) << t.warnings[0];
}

TEST(C3dReader, SyntheticFileInEveryProcessorFormat) {
  for (const std::uint8_t processor : {84, 85, 86}) {
    const std::vector<std::uint8_t> bytes = SyntheticFile(processor);
    const Trial t = ReadC3dFromMemory(bytes, "synthetic.c3d");
    SCOPED_TRACE(t.source.processor);
    EXPECT_TRUE(t.warnings.empty()) << t.warnings.front();
    EXPECT_EQ(t.source.processor, processor == 84 ? "Intel" : processor == 85 ? "DEC" : "MIPS");
    EXPECT_EQ(t.source.point_storage, "integer");
    EXPECT_EQ(t.num_frames, 3);
    EXPECT_EQ(t.first_frame, 5);
    EXPECT_EQ(t.point_rate_hz, 100);
    EXPECT_EQ(t.analog_rate_hz, 200);
    ASSERT_EQ(t.num_points(), 2);
    EXPECT_EQ(t.points[0].label, "TOE");
    EXPECT_EQ(t.points[1].label, "HEEL");
    // x = raw × POINT:SCALE, in mm → m.
    EXPECT_DOUBLE_EQ(t.position(2, 0)(0), 102 * 0.5 * 1e-3);
    EXPECT_DOUBLE_EQ(t.position(0, 0)(1), -200 * 0.5 * 1e-3);
    EXPECT_DOUBLE_EQ(t.position(2, 1)(0), -402 * 0.5 * 1e-3);
    EXPECT_EQ(t.residuals(0, 0), 5.0f);
    EXPECT_EQ(t.camera_masks(0, 0), 3);
    EXPECT_TRUE(std::isnan(t.position(1, 1)(0)));
    EXPECT_EQ(t.residuals(1, 1), -1.0f);
    EXPECT_EQ(t.residuals(1, 2), 0.0f);
    // Unsigned analog: (raw − OFFSET) × SCALE × GEN_SCALE with raw and OFFSET unsigned (SCALE is a
    // float parameter: 0.01f).
    ASSERT_EQ(t.num_analog_channels(), 2);
    EXPECT_EQ(t.analog_channels[0].offset, 32768);
    EXPECT_EQ(t.analog_samples_per_frame(), 2);
    EXPECT_NEAR(t.analog(0, 0), (40000 - 32768) * double(0.01f) * 2, 1e-9);
    EXPECT_NEAR(t.analog(0, 5), (40021 - 32768) * double(0.01f) * 2, 1e-9);
    EXPECT_NEAR(t.analog(1, 3), (1000 - 2048) * -0.5 * 2, 1e-9);
    // Header events with their display flags.
    ASSERT_EQ(t.events.size(), 2u);
    EXPECT_EQ(t.events[0].label, "HS");
    EXPECT_EQ(t.events[0].time_s, 0.25);
    EXPECT_TRUE(t.events[0].displayed);
    EXPECT_EQ(t.events[1].label, "TO");
    EXPECT_FALSE(t.events[1].displayed);
    // Parameters: the group record after its parameter, locked flags, descriptions, group ids.
    const ParameterGroup* point = t.parameters.FindGroup("POINT");
    ASSERT_NE(point, nullptr);
    EXPECT_EQ(point->id, 1);
    EXPECT_EQ(point->description, "3D points");
    EXPECT_FALSE(point->locked);
    EXPECT_TRUE(t.parameters.FindGroup("ANALOG")->locked);
    EXPECT_TRUE(t.parameters.Find("POINT", "USED")->locked);
    EXPECT_EQ(t.parameters.Find("POINT", "USED")->description, "number of points");
    EXPECT_EQ(t.parameters.FindString("ANALOG", "FORMAT").value(), "UNSIGNED");
    // Written as Intel float and read again: analog exact, the locked flags and the group order
    // kept.
    const Trial back = ReadC3dFromMemory(WriteC3dToMemory(t), "synthetic-written.c3d");
    EXPECT_TRUE(back.analog == t.analog);
    EXPECT_EQ(back.source.processor, "Intel");
    EXPECT_EQ(back.source.point_storage, "float");
    EXPECT_TRUE(back.parameters.FindGroup("ANALOG")->locked);
    EXPECT_TRUE(back.parameters.Find("POINT", "USED")->locked);
    EXPECT_EQ(back.parameters.groups()[0].name, "POINT");
    EXPECT_EQ(back.events.size(), 2u);
    EXPECT_FALSE(back.events[1].displayed);
  }
}

// ---------------------------------------------------------------------------------------------
// Files that load with warnings, and files that must fail.
TEST(C3dReader, EmptyFileFailsNamingTheFile) {
  const auto path = RefdataFile("BTKData/Input/C3DSamples/others/Empty.c3d");
  ACRO_REQUIRE_REFDATA_FILE(path);
  try {
    ReadC3d(path);
    FAIL() << "Empty.c3d loaded";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("Empty.c3d"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("empty"), std::string::npos) << e.what();
  }
}

// Decision: sample_18 fails (as in BTK and c3dio): its parameter section runs into the data section
// (EVENT:LABELS crosses the data start block), so the parameters cannot be trusted.
TEST(C3dReader, Sample18BadParameterSectionFails) {
  const auto path = RefdataFile(std::string(kOrg) + "sample_18/bad_parameter_section.c3d");
  ACRO_REQUIRE_REFDATA_FILE(path);
  try {
    ReadC3d(path);
    FAIL() << "bad_parameter_section.c3d loaded";
  } catch (const InputError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("bad_parameter_section.c3d"), std::string::npos) << what;
    EXPECT_NE(what.find("EVENT:LABELS"), std::string::npos) << what;
    EXPECT_NE(what.find("bad data first block"), std::string::npos) << what;
  }
}

TEST(C3dReader, BadParameterOffsetLoads) {
  const auto path = RefdataFile("BTKData/Input/C3DSamples/others/badParameterOffset.c3d");
  ACRO_REQUIRE_REFDATA_FILE(path);
  const Trial t = ReadC3d(path);
  EXPECT_EQ(t.events.size(), 0u);
  EXPECT_EQ(t.num_points(), 41);
  EXPECT_EQ(t.num_analog_channels(), 0);
  EXPECT_EQ(t.first_frame, 1);
  EXPECT_EQ(t.first_frame + t.num_frames - 1, 111);
  EXPECT_EQ(t.point_rate_hz, 250.0);
  EXPECT_EQ(t.points[0].label, "Point    1");
  EXPECT_EQ(t.points[40].label, "Point   41");
  EXPECT_NEAR(Mm(t, 0, 0, 0), 168.093002, 1e-5);
  EXPECT_NEAR(Mm(t, 10, 29, 1), 731.903015, 1e-5);
  // BTK's 0.0 is the file's (0, 0, 0) of a sample whose residual word is -1: here a gap (NaN).
  EXPECT_TRUE(std::isnan(Mm(t, 110, 40, 2)));
  EXPECT_EQ(t.residuals(40, 110), -1.0f);
  EXPECT_FALSE(t.warnings.empty());  // ANALOG:UNITS overruns its record
}

TEST(C3dReader, Utf8Path) {
  const auto path =
      RefdataFile("BTKData/Input/C3DSamples/others/Я могу есть стекло/оно мне не вредит.c3d");
  ACRO_REQUIRE_REFDATA_FILE(path);
  const Trial t = ReadC3d(path);
  EXPECT_EQ(t.events.size(), 0u);
  EXPECT_EQ(t.num_points(), 27);
  EXPECT_EQ(t.num_analog_channels(), 6);
  EXPECT_EQ(t.first_frame, 91);
  EXPECT_EQ(t.first_frame + t.num_frames - 1, 327);
  EXPECT_EQ(t.point_rate_hz, 250.0);
  EXPECT_EQ(t.analog_rate_hz, 1000.0);
  EXPECT_EQ(t.points[0].label, "AbcdeFghijk:RASI");
  EXPECT_EQ(t.points[26].label, "AbcdeFghijk:LFIN");
  EXPECT_EQ(t.FindPoint("RASI"), 0);
  EXPECT_EQ(t.FindPoint("AbcdeFghijk:LFIN"), 26);
  EXPECT_EQ(t.FindPoint("NOPE"), -1);
}

TEST(C3dReader, ParameterOverflowKeepsParameterBeyondSection) {
  const auto path = RefdataFile("BTKData/Input/C3DSamples/others/parameterOverflow.c3d");
  ACRO_REQUIRE_REFDATA_FILE(path);
  const Trial t = ReadC3d(path);
  ASSERT_NE(t.parameters.FindGroup("ANALYSIS"), nullptr);
  EXPECT_NE(t.parameters.Find("ANALYSIS", "VALUES"), nullptr);
  EXPECT_FALSE(t.warnings.empty());
}

TEST(C3dReader, Mocap36LoadsDespiteMissingDescriptionLength) {
  const auto path = RefdataFile("BTKData/Input/C3DSamples/others/mocap36.c3d");
  ACRO_REQUIRE_REFDATA_FILE(path);
  const Trial t = ReadC3d(path);
  EXPECT_EQ(t.num_points(), 36);
  EXPECT_EQ(t.num_frames, 1380);
  EXPECT_EQ(t.point_rate_hz, 100);
  ASSERT_EQ(t.warnings.size(), 1u);
  EXPECT_NE(t.warnings[0].find("POINT:LABELS"), std::string::npos) << t.warnings[0];
  EXPECT_NE(t.warnings[0].find("no description length byte"), std::string::npos) << t.warnings[0];
}

}  // namespace
}  // namespace acro::capture
