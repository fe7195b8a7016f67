// C3D writer: read → write → read over every loadable file of the c3d.org and BTK suites.
// What must hold (c3dio's round-trip criterion, made stricter):
//  - every parameter, label, description, unit, rate, event, force-plate definition and the
//    subject are identical after the round trip; the only parameters that may change are those
//    describing the layout (POINT:USED, SCALE, FRAMES, DATA_START, ANALOG:USED), which must still
//    describe the same trial;
//  - analog samples are identical (integer sources: the raw integers are exact in float32);
//  - points and residuals are identical for float sources; an integer source is converted to float
//    on the first write, so its coordinates equal the original within float32 rounding
//    (relative 2⁻²⁴), and from then on a second write → read is bit-identical (the written bytes
//    are a fixed point: write(read(write(read(file)))) == write(read(file))).

#include <cmath>
#include <filesystem>
#include <set>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "acro/base/input_error.h"
#include "acro/capture/c3d.h"
#include "refdata.h"

namespace acro::capture {
namespace {

namespace fs = std::filesystem;

// Every .c3d file of both suites, sorted (the UTF-8 path included).
std::vector<fs::path> SuiteFiles() {
  std::vector<fs::path> files;
  for (const char* suite : {"c3dio-c3d_org_samples", "BTKData"}) {
    const fs::path dir = acro::testing::RefdataDir() / suite;
    if (!fs::exists(dir)) continue;
    for (const auto& entry : fs::recursive_directory_iterator(dir)) {
      std::string ext = entry.path().extension().string();
      for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
      if (entry.is_regular_file() && ext == ".c3d") files.push_back(entry.path());
    }
  }
  std::sort(files.begin(), files.end());
  return files;
}

// Files that must not load (tested with their messages in c3d_reader_test and c3d_bad_input_test).
bool ExpectedToFail(const fs::path& p) {
  const std::string name = p.filename().string();
  return name == "Empty.c3d" || name == "bad_parameter_section.c3d";
}

bool SameParameter(const Parameter& a, const Parameter& b) {
  return a.name == b.name && a.description == b.description && a.locked == b.locked &&
         a.type == b.type && a.dimensions == b.dimensions && a.chars == b.chars &&
         a.bytes == b.bytes && a.int16s == b.int16s && a.floats.size() == b.floats.size() &&
         std::equal(a.floats.begin(), a.floats.end(), b.floats.begin(), [](float x, float y) {
           return std::memcmp(&x, &y, 4) == 0;  // bit-identical, NaN included
         });
}

bool IsLayoutParameter(const std::string& group, const std::string& name) {
  static const std::set<std::string> kLayout = {
      "POINT:USED", "POINT:SCALE", "POINT:FRAMES", "POINT:DATA_START", "ANALOG:USED"};
  return kLayout.count(group + ":" + name) > 0;
}

void ExpectSameMetadata(const Trial& a, const Trial& b, const std::string& file) {
  EXPECT_EQ(a.num_frames, b.num_frames) << file;
  EXPECT_EQ(a.first_frame, b.first_frame) << file;
  EXPECT_EQ(a.point_rate_hz, b.point_rate_hz) << file;
  EXPECT_EQ(a.analog_rate_hz, b.analog_rate_hz) << file;
  EXPECT_EQ(a.subject_name, b.subject_name) << file;
  EXPECT_EQ(a.source.point_units, b.source.point_units) << file;
  EXPECT_EQ(a.source.point_units_to_m, b.source.point_units_to_m) << file;
  EXPECT_EQ(std::abs(a.source.point_scale), std::abs(b.source.point_scale)) << file;
  EXPECT_EQ(a.source.max_interpolation_gap, b.source.max_interpolation_gap) << file;
  ASSERT_EQ(a.num_points(), b.num_points()) << file;
  for (int i = 0; i < a.num_points(); ++i) {
    EXPECT_EQ(a.points[i].label, b.points[i].label) << file;
    EXPECT_EQ(a.points[i].description, b.points[i].description) << file;
    EXPECT_EQ(a.points[i].type, b.points[i].type) << file;
    EXPECT_EQ(a.points[i].unit, b.points[i].unit) << file;
  }
  ASSERT_EQ(a.num_analog_channels(), b.num_analog_channels()) << file;
  for (int i = 0; i < a.num_analog_channels(); ++i) {
    EXPECT_EQ(a.analog_channels[i].label, b.analog_channels[i].label) << file;
    EXPECT_EQ(a.analog_channels[i].description, b.analog_channels[i].description) << file;
    EXPECT_EQ(a.analog_channels[i].unit, b.analog_channels[i].unit) << file;
    EXPECT_EQ(a.analog_channels[i].scale, b.analog_channels[i].scale) << file;
    EXPECT_EQ(a.analog_channels[i].offset, b.analog_channels[i].offset) << file;
    EXPECT_EQ(a.analog_channels[i].gain_code, b.analog_channels[i].gain_code) << file;
  }
  ASSERT_EQ(a.events.size(), b.events.size()) << file;
  for (std::size_t i = 0; i < a.events.size(); ++i) {
    EXPECT_EQ(a.events[i].label, b.events[i].label) << file;
    EXPECT_EQ(a.events[i].context, b.events[i].context) << file;
    EXPECT_EQ(a.events[i].description, b.events[i].description) << file;
    EXPECT_EQ(a.events[i].subject, b.events[i].subject) << file;
    EXPECT_EQ(a.events[i].time_s, b.events[i].time_s) << file;
    EXPECT_EQ(a.events[i].displayed, b.events[i].displayed) << file;
  }
  ASSERT_EQ(a.force_plates.size(), b.force_plates.size()) << file;
  for (std::size_t i = 0; i < a.force_plates.size(); ++i) {
    const ForcePlate& x = a.force_plates[i];
    const ForcePlate& y = b.force_plates[i];
    EXPECT_EQ(x.type, y.type) << file;
    EXPECT_EQ(x.corners_W_m, y.corners_W_m) << file;
    EXPECT_EQ(x.origin_F_m, y.origin_F_m) << file;
    EXPECT_EQ(x.channels, y.channels) << file;
    EXPECT_EQ(x.zero, y.zero) << file;
    EXPECT_TRUE(x.cal_matrix.size() == y.cal_matrix.size() && x.cal_matrix == y.cal_matrix) << file;
    // Outputs are recomputed from identical analog samples: identical (NaN where NaN).
    EXPECT_TRUE(x.force_W_N.isApprox(y.force_W_N, 0) || x.force_W_N == y.force_W_N) << file;
  }
  // Parameters: every group and parameter of `a` in `b`, in the same order (files may hold two
  // groups of one name, c3d.org sample 33), identical except the layout ones; the writer may only
  // append.
  const auto& ga = a.parameters.groups();
  const auto& gb = b.parameters.groups();
  ASSERT_GE(gb.size(), ga.size()) << file;
  for (std::size_t i = 0; i < ga.size(); ++i) {
    EXPECT_EQ(ga[i].name, gb[i].name) << file;
    EXPECT_EQ(ga[i].id, gb[i].id) << file << " group " << ga[i].name;
    EXPECT_EQ(ga[i].description, gb[i].description) << file << " group " << ga[i].name;
    EXPECT_EQ(ga[i].locked, gb[i].locked) << file << " group " << ga[i].name;
    ASSERT_GE(gb[i].parameters.size(), ga[i].parameters.size()) << file << " group " << ga[i].name;
    for (std::size_t j = 0; j < ga[i].parameters.size(); ++j) {
      const Parameter& p = ga[i].parameters[j];
      const Parameter& q = gb[i].parameters[j];
      ASSERT_EQ(p.name, q.name) << file << " group " << ga[i].name;
      if (IsLayoutParameter(ga[i].name, p.name)) continue;
      EXPECT_TRUE(SameParameter(p, q)) << file << " " << ga[i].name << ":" << p.name;
    }
  }
}

TEST(C3dWriter, RoundTripEverySuiteFile) {
  const std::vector<fs::path> files = SuiteFiles();
  if (files.empty()) ACRO_REQUIRE_REFDATA_FILE(acro::testing::RefdataFile("c3dio-c3d_org_samples"));
  int checked = 0;
  for (const fs::path& path : files) {
    const std::string file = path.string();
    if (ExpectedToFail(path)) continue;
    SCOPED_TRACE(file);
    const Trial t1 = ReadC3d(path);
    const std::vector<std::uint8_t> bytes1 = WriteC3dToMemory(t1);
    const Trial t2 = ReadC3dFromMemory(bytes1, file + " (written)");
    ExpectSameMetadata(t1, t2, file);

    // Analog: identical.
    ASSERT_EQ(t1.analog.rows(), t2.analog.rows());
    ASSERT_EQ(t1.analog.cols(), t2.analog.cols());
    EXPECT_TRUE(t1.analog == t2.analog) << file;

    // Points: identical for float sources; float32 rounding of the original for integer sources.
    ASSERT_EQ(t1.positions.cols(), t2.positions.cols());
    const bool float_source = t1.source.point_storage == "float";
    double worst_relative = 0;
    for (Eigen::Index i = 0; i < t1.positions.cols(); ++i) {
      for (int k = 0; k < 3; ++k) {
        const double x1 = t1.positions(k, i);
        const double x2 = t2.positions(k, i);
        ASSERT_EQ(std::isnan(x1), std::isnan(x2)) << file << " sample " << i;
        if (std::isnan(x1)) continue;
        if (float_source) {
          ASSERT_EQ(x1, x2) << file << " sample " << i;
        } else if (x1 != 0) {
          worst_relative = std::max(worst_relative, std::abs(x2 - x1) / std::abs(x1));
        } else {
          ASSERT_EQ(x2, 0.0) << file << " sample " << i;
        }
      }
    }
    EXPECT_LE(worst_relative, std::ldexp(1.0, -24) + 1e-15) << file;
    EXPECT_TRUE((t1.residuals == t2.residuals).all()) << file;
    EXPECT_TRUE((t1.camera_masks == t2.camera_masks).all()) << file;

    // Second generation: bit-identical bytes and values.
    const std::vector<std::uint8_t> bytes2 = WriteC3dToMemory(t2);
    EXPECT_TRUE(bytes1 == bytes2) << file << ": second write differs (" << bytes1.size() << " vs "
                                  << bytes2.size() << " bytes)";
    const Trial t3 = ReadC3dFromMemory(bytes2, file + " (written twice)");
    EXPECT_TRUE(t3.positions.cwiseEqual(t2.positions).count() +
                    t2.positions.array().isNaN().count() ==
                t2.positions.size())
        << file;
    ++checked;
  }
  EXPECT_GE(checked, 70) << "round trip ran on too few files";
}

// A trial made by code (as the TRC importer or a generator makes one): no parameters. The writer
// creates them; the file reads back to the same trial within float32 rounding, and a second write
// is bit-identical.
Trial MakeTrial(int frames, std::int64_t first_frame) {
  Trial t;
  t.source.format = "generated";
  t.point_rate_hz = 100;
  t.first_frame = first_frame;
  t.num_frames = frames;
  t.subject_name = "Athlete";
  for (const char* label : {"LASI", "RASI", "HEAD"})
    t.points.push_back({label, std::string(label) + " marker", PointType::kMarker, "m"});
  PointInfo angle{"LKneeAngles", "knee", PointType::kAngle, "deg"};
  t.points.push_back(angle);
  t.positions.resize(3, std::int64_t(frames) * 4);
  for (int f = 0; f < frames; ++f) {
    for (int p = 0; p < 4; ++p) {
      t.position(f, p) << 0.1 * p + 0.001 * f, 1.0 + 0.5 * std::sin(0.01 * f), 0.9 + 0.01 * p;
    }
  }
  t.position(frames / 2, 1).setConstant(std::nan(""));  // a gap
  t.position(3, 3) << 12.5, -40.25, 3.0;                // degrees, not scaled
  t.analog_rate_hz = 1000;
  const char* units[6] = {"N", "N", "N", "Nmm", "Nmm", "Nmm"};
  for (int c = 0; c < 6; ++c)
    t.analog_channels.push_back({"F" + std::to_string(c), "", units[c], 0.5, 0.0, 0.0});
  t.analog.resize(6, std::int64_t(frames) * 10);
  for (Eigen::Index s = 0; s < t.analog.cols(); ++s) {
    for (int c = 0; c < 6; ++c)
      t.analog(c, s) = (c == 2 ? -600.0 : 10.0 * c) + 0.25 * std::cos(0.003 * s);
  }
  ForcePlate plate;
  plate.type = 2;
  plate.corners_W_m << 0.6, 0, 0, 0.6, 0, 0, 0.4, 0.4, 0, 0, 0, 0;
  plate.origin_F_m << 0.001, -0.002, -0.04;
  plate.channels = {0, 1, 2, 3, 4, 5};
  plate.zero = {0, 0};
  t.force_plates.push_back(plate);
  t.events.push_back({"Foot Strike", "Left", "heel contact", "Athlete", 0.125, true, 1, 0});
  t.events.push_back({"Foot Off", "Right", "", "Athlete", 75.5, true, 2, 0});
  return t;
}

TEST(C3dWriter, GeneratedTrialRoundTrip) {
  const Trial t = MakeTrial(200, 10);
  const std::vector<std::uint8_t> bytes = WriteC3dToMemory(t);
  const Trial back = ReadC3dFromMemory(bytes, "generated.c3d");
  EXPECT_TRUE(back.warnings.empty()) << back.warnings.front();
  EXPECT_EQ(back.num_frames, 200);
  EXPECT_EQ(back.first_frame, 10);
  EXPECT_EQ(back.point_rate_hz, 100);
  EXPECT_EQ(back.analog_rate_hz, 1000);
  EXPECT_EQ(back.subject_name, "Athlete");
  EXPECT_EQ(back.source.point_units, "mm");
  ASSERT_EQ(back.num_points(), 4);
  for (int p = 0; p < 4; ++p) {
    EXPECT_EQ(back.points[p].label, t.points[p].label);
    EXPECT_EQ(back.points[p].description, t.points[p].description);
    EXPECT_EQ(back.points[p].type, t.points[p].type);
  }
  EXPECT_EQ(back.points[3].unit, "deg");
  // Within float32 rounding of the millimetre (markers) or degree (angle) values.
  for (Eigen::Index i = 0; i < t.positions.cols(); ++i) {
    for (int k = 0; k < 3; ++k) {
      const double a = t.positions(k, i), b = back.positions(k, i);
      ASSERT_EQ(std::isnan(a), std::isnan(b)) << i;
      if (!std::isnan(a)) {
        ASSERT_LE(std::abs(a - b), std::abs(a) * std::ldexp(1.0, -24) + 1e-15) << i;
      }
    }
  }
  EXPECT_EQ(back.position(3, 3)(1), -40.25);
  ASSERT_EQ(back.num_analog_channels(), 6);
  for (int c = 0; c < 6; ++c) {
    EXPECT_EQ(back.analog_channels[c].label, t.analog_channels[c].label);
    EXPECT_EQ(back.analog_channels[c].unit, t.analog_channels[c].unit);
    EXPECT_EQ(back.analog_channels[c].scale, 0.5);
  }
  ASSERT_EQ(back.analog.cols(), t.analog.cols());
  EXPECT_LE((back.analog - t.analog).cwiseAbs().maxCoeff(), 600 * std::ldexp(1.0, -24));
  ASSERT_EQ(back.force_plates.size(), 1u);
  EXPECT_EQ(back.force_plates[0].type, 2);
  EXPECT_EQ(back.force_plates[0].channels, t.force_plates[0].channels);
  EXPECT_LE(
      (back.force_plates[0].corners_W_m - t.force_plates[0].corners_W_m).cwiseAbs().maxCoeff(),
      1e-9);
  EXPECT_LE((back.force_plates[0].origin_F_m - t.force_plates[0].origin_F_m).cwiseAbs().maxCoeff(),
            1e-9);
  ASSERT_EQ(back.force_plates[0].force_W_N.cols(), t.analog.cols());
  EXPECT_GT(back.force_plates[0].force_W_N(2, 0), 590);  // FZ −600 N in F (z down): 600 N up in W
  ASSERT_EQ(back.events.size(), 2u);
  for (int i = 0; i < 2; ++i) {
    EXPECT_EQ(back.events[i].label, t.events[i].label);
    EXPECT_EQ(back.events[i].context, t.events[i].context);
    EXPECT_EQ(back.events[i].description, t.events[i].description);
    EXPECT_EQ(back.events[i].subject, t.events[i].subject);
    EXPECT_EQ(back.events[i].icon_id, t.events[i].icon_id);
    EXPECT_NEAR(back.events[i].time_s, t.events[i].time_s, 1e-5);  // minutes + float seconds
  }
  // Second generation: bit-identical.
  EXPECT_TRUE(WriteC3dToMemory(back) == bytes);
}

// More than 65535 frames (C3D manual: header frame numbers are 16-bit): TRIAL:ACTUAL_START_FIELD /
// ACTUAL_END_FIELD and a float POINT:FRAMES carry the count.
TEST(C3dWriter, MoreThan65535Frames) {
  for (const std::int64_t first : {std::int64_t(1), std::int64_t(65000)}) {
    Trial t;
    t.source.format = "generated";
    t.point_rate_hz = 1000;
    t.first_frame = first;
    t.num_frames = 70000;
    t.points.push_back({"M", "", PointType::kMarker, "m"});
    t.positions.resize(3, t.num_frames);
    for (int f = 0; f < t.num_frames; ++f) t.position(f, 0) << f * 1e-6, 0.5, 1.0;
    const std::vector<std::uint8_t> bytes = WriteC3dToMemory(t);
    const Trial back = ReadC3dFromMemory(bytes, "long.c3d");
    EXPECT_EQ(back.num_frames, 70000);
    EXPECT_EQ(back.first_frame, first);
    EXPECT_NEAR(back.position(69999, 0)(0), 0.069999, 1e-9);
    const Parameter* frames = back.parameters.Find("POINT", "FRAMES");
    ASSERT_NE(frames, nullptr);
    EXPECT_EQ(frames->type, ParameterType::kFloat);
    EXPECT_EQ(frames->floats[0], 70000.0f);
    const Parameter* end = back.parameters.Find("TRIAL", "ACTUAL_END_FIELD");
    ASSERT_NE(end, nullptr);
    EXPECT_EQ(end->AsUnsigned()[0] | (end->AsUnsigned()[1] << 16), std::uint32_t(first + 69999));
    EXPECT_TRUE(WriteC3dToMemory(back) == bytes);
    // A writer that lets the 16-bit header last frame wrap around (70000 + first − 1 mod 65536):
    // the TRIAL range still gives the count.
    std::vector<std::uint8_t> wrapped = bytes;
    const std::uint16_t last16 = static_cast<std::uint16_t>((first + 69999) & 0xFFFF);
    wrapped[8] = static_cast<std::uint8_t>(last16 & 0xFF);
    wrapped[9] = static_cast<std::uint8_t>(last16 >> 8);
    const Trial again = ReadC3dFromMemory(wrapped, "wrapped.c3d");
    EXPECT_EQ(again.num_frames, 70000);
    EXPECT_EQ(again.first_frame, first);
  }
}

// More than 255 points, channels and events: LABELS2, SCALE2, OFFSET2, TIMES2 … continuations.
TEST(C3dWriter, MoreThan255PointsChannelsAndEvents) {
  Trial t;
  t.source.format = "generated";
  t.point_rate_hz = 50;
  t.num_frames = 3;
  for (int p = 0; p < 300; ++p)
    t.points.push_back({"P" + std::to_string(p), "", PointType::kMarker, "m"});
  t.positions = Eigen::Matrix3Xd::Constant(3, 3 * 300, 0.25);
  t.analog_rate_hz = 100;
  for (int c = 0; c < 300; ++c) {
    t.analog_channels.push_back({"C" + std::to_string(c), "", "V", 0.5 + c, double(c - 100), 0.0});
  }
  t.analog = Eigen::MatrixXd::Constant(300, 6, 3.0);
  for (int e = 0; e < 300; ++e)
    t.events.push_back({"E" + std::to_string(e), "General", "", "", 0.01 * e, true, 0, 0});
  const Trial back = ReadC3dFromMemory(WriteC3dToMemory(t), "many.c3d");
  EXPECT_TRUE(back.warnings.empty()) << back.warnings.front();
  ASSERT_EQ(back.num_points(), 300);
  EXPECT_EQ(back.points[299].label, "P299");
  EXPECT_NE(back.parameters.Find("POINT", "LABELS2"), nullptr);
  ASSERT_EQ(back.num_analog_channels(), 300);
  EXPECT_EQ(back.analog_channels[299].label, "C299");
  EXPECT_EQ(back.analog_channels[299].scale, 299.5);
  EXPECT_EQ(back.analog_channels[299].offset, 199);
  EXPECT_NE(back.parameters.Find("ANALOG", "SCALE2"), nullptr);
  // Raw samples are floats: value / scale + offset rounded to float32, so the error is that of the
  // raw value (|raw| < 200) times the scale (< 300).
  EXPECT_LE((back.analog - t.analog).cwiseAbs().maxCoeff(), 200 * std::ldexp(1.0, -24) * 300);
  ASSERT_EQ(back.events.size(), 300u);
  EXPECT_EQ(back.events[299].label, "E299");
  EXPECT_EQ(back.events[299].context, "General");
  EXPECT_NEAR(back.events[299].time_s, 2.99, 1e-6);
}

// A trial cropped in code: the layout parameters (POINT:FRAMES, TRIAL:ACTUAL_*_FIELD) follow.
TEST(C3dWriter, CroppedTrialKeepsLayoutInStep) {
  const auto path = acro::testing::RefdataFile("c3dio-c3d_org_samples/sample_09/PlugInC3D.c3d");
  ACRO_REQUIRE_REFDATA_FILE(path);
  Trial t = ReadC3d(path);
  const int P = t.num_points();
  const int spf = t.analog_samples_per_frame();
  const int begin = 10, count = 100;
  Trial cropped = t;
  cropped.first_frame = t.first_frame + begin;
  cropped.num_frames = count;
  cropped.positions = t.positions.middleCols(std::int64_t(begin) * P, std::int64_t(count) * P);
  cropped.residuals = t.residuals.middleCols(begin, count);
  cropped.camera_masks = t.camera_masks.middleCols(begin, count);
  cropped.analog = t.analog.middleCols(std::int64_t(begin) * spf, std::int64_t(count) * spf);
  const Trial back = ReadC3dFromMemory(WriteC3dToMemory(cropped), "cropped.c3d");
  EXPECT_EQ(back.first_frame, 11);
  EXPECT_EQ(back.num_frames, 100);
  EXPECT_EQ(back.parameters.Find("POINT", "FRAMES")->AsUnsigned()[0], 100u);
  EXPECT_EQ(back.parameters.Find("TRIAL", "ACTUAL_START_FIELD")->AsUnsigned()[0], 11u);
  EXPECT_EQ(back.parameters.Find("TRIAL", "ACTUAL_END_FIELD")->AsUnsigned()[0], 110u);
  EXPECT_TRUE(back.analog == cropped.analog);
  EXPECT_EQ(back.warnings.size(), t.warnings.size());  // only the file's own (ORIGIN z > 0)
}

// A gap filled in code (coordinates set, residual still −1) is written as a valid sample.
TEST(C3dWriter, FilledGapIsWrittenValid) {
  const auto path = acro::testing::RefdataFile("c3dio-c3d_org_samples/sample_01/Eb015pr.c3d");
  ACRO_REQUIRE_REFDATA_FILE(path);
  Trial t = ReadC3d(path);
  Eigen::Index gap = -1;
  for (Eigen::Index i = 0; i < t.positions.cols() && gap < 0; ++i) {
    if (std::isnan(t.positions(0, i))) gap = i;
  }
  ASSERT_GE(gap, 0);
  const int frame = static_cast<int>(gap / t.num_points()),
            point = static_cast<int>(gap % t.num_points());
  ASSERT_EQ(t.residuals(point, frame), -1.0f);
  t.positions.col(gap) << 0.5, 0.25, 0.125;
  const Trial back = ReadC3dFromMemory(WriteC3dToMemory(t), "filled.c3d");
  EXPECT_TRUE(back.valid(frame, point));
  EXPECT_EQ(back.position(frame, point)(0), 0.5);
  EXPECT_EQ(back.residuals(point, frame), 0.0f);
  EXPECT_TRUE(back.warnings.empty()) << back.warnings.front();
}

TEST(C3dWriter, WriteC3dRenamesIntoPlace) {
  const auto path = acro::testing::RefdataFile("c3dio-c3d_org_samples/sample_01/Eb015pr.c3d");
  ACRO_REQUIRE_REFDATA_FILE(path);
  const Trial t = ReadC3d(path);
  const fs::path out = acro::testing::TempDir() / "writer_eb015.c3d";
  WriteC3d(t, out);
  EXPECT_TRUE(fs::exists(out));
  // No temporary left beside it (WriteFileAtomically's unique ".<name>.tmpNNN").
  for (const auto& e : fs::directory_iterator(out.parent_path()))
    EXPECT_NE(e.path().filename().string().rfind("." + out.filename().string() + ".tmp", 0), 0u)
        << e.path();
  const Trial back = ReadC3d(out);
  EXPECT_EQ(back.num_frames, 450);
  EXPECT_TRUE(back.positions.cwiseEqual(t.positions).count() +
                  t.positions.array().isNaN().count() ==
              t.positions.size());
}

TEST(C3dWriter, UnwritableTargetThrowsNamingIt) {
  Trial t;
  t.point_rate_hz = 100;
  const fs::path out = acro::testing::TempDir() / "no_such_dir" / "x.c3d";
  try {
    WriteC3d(t, out);
    FAIL() << "wrote into a missing directory";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("x.c3d"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace acro::capture
