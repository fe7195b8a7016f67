// The pose networks' conversion (tools/pose_model_conversion.h): the TFLite reader on small models
// built here with known answers (float16 weights behind DEQUANTIZE, a CSR-sparse constant behind
// DENSIFY), its refusals, and the four BlazePose networks converted and run by OpenCV's DNN
// against an independent evaluation of the TFLite graph (support/tflite_reference.h): ≤ 1e-3
// relative on every output. Converting twice gives the same bytes, the bytes install-models.sh
// pinned.

#include <cmath>
#include <cstring>
#include <random>

#include <flatbuffers/flatbuffers.h>
#include <gtest/gtest.h>
#include <opencv2/dnn.hpp>
#include <opencv2/imgproc.hpp>

#include "acro/base/file_io.h"
#include "acro/base/input_error.h"
#include "acro/capture/video.h"
#include "acro/pose/tflite_graph.h"
#include "pose_model_conversion.h"
#include "pose_model_cache.h"
#include "refdata.h"
#include "tflite_reference.h"

namespace acro {
namespace {

namespace fb = flatbuffers;
constexpr fb::voffset_t F(int i) { return static_cast<fb::voffset_t>(4 + 2 * i); }

// float32 → IEEE binary16 for values exactly representable (the test's weights are).
uint16_t ToHalf(float f) {
  uint32_t x;
  std::memcpy(&x, &f, 4);
  const uint32_t sign = (x >> 16) & 0x8000u;
  const int exponent = static_cast<int>((x >> 23) & 0xff) - 127 + 15;
  const uint32_t mantissa = (x >> 13) & 0x3ffu;
  if ((x & 0x7fffffffu) == 0) return static_cast<uint16_t>(sign);
  return static_cast<uint16_t>(sign | (static_cast<uint32_t>(exponent) << 10) | mantissa);
}

template <typename T>
std::vector<uint8_t> Bytes(const std::vector<T>& values) {
  std::vector<uint8_t> out(values.size() * sizeof(T));
  std::memcpy(out.data(), values.data(), out.size());
  return out;
}

// A small TFLite model written by field index (the schema's declaration order), as a converter
// would: input [1,3,3,2] → CONV_2D 1×1 (float16 weights through DEQUANTIZE, bias, RELU6) → A;
// input → CONV_2D 1×1 (CSR-sparse float32 weights through DENSIFY, no bias) → B. `op_code` replaces
// the first convolution's operator code (a refusal test); `truncate` cuts the file.
struct TinyModel {
  std::vector<float> w1 = {1.0f, -2.0f, 0.5f, 3.0f};  // [O=2][I=2]
  std::vector<float> b1 = {0.25f, -1.0f};
  std::vector<float> w2_dense = {0.0f, 5.0f, 7.0f, 0.0f};
  int op_code = 3;

  std::vector<uint8_t> Build() const {
    fb::FlatBufferBuilder b;
    // Buffers: 0 empty (TFLite's sentinel), 1 fp16 w1, 2 b1, 3 sparse values of w2.
    std::vector<std::vector<uint8_t>> data = {{}, {}, Bytes(b1), Bytes(std::vector<float>{5.0f, 7.0f})};
    std::vector<uint16_t> half;
    for (float v : w1) half.push_back(ToHalf(v));
    data[1] = Bytes(half);
    std::vector<fb::Offset<fb::Table>> buffers;
    for (const auto& d : data) {
      const auto vec = d.empty() ? fb::Offset<fb::Vector<uint8_t>>() : b.CreateVector(d);
      const auto start = b.StartTable();
      if (!d.empty()) b.AddOffset(F(0), vec);
      buffers.push_back(fb::Offset<fb::Table>(b.EndTable(start)));
    }
    // The sparse weights' metadata: dims dense 2, dense 1, dense 1, CSR (segments 0 1 2, indices 1 0).
    auto index_vector = [&](const std::vector<int32_t>& values) {
      const auto vec = b.CreateVector(values);
      const auto start = b.StartTable();
      b.AddOffset(F(0), vec);
      return fb::Offset<fb::Table>(b.EndTable(start));
    };
    std::vector<fb::Offset<fb::Table>> dims;
    for (int k = 0; k < 4; ++k) {
      fb::Offset<fb::Table> segments, indices;
      if (k == 3) {
        segments = index_vector({0, 1, 2});
        indices = index_vector({1, 0});
      }
      const auto start = b.StartTable();
      b.AddElement<int8_t>(F(0), k == 3 ? 1 : 0, 0);
      b.AddElement<int32_t>(F(1), k == 0 ? 2 : 1, 0);
      if (k == 3) {
        b.AddElement<uint8_t>(F(2), 1, 0);  // Int32Vector
        b.AddOffset(F(3), segments);
        b.AddElement<uint8_t>(F(4), 1, 0);
        b.AddOffset(F(5), indices);
      }
      dims.push_back(fb::Offset<fb::Table>(b.EndTable(start)));
    }
    const auto traversal = b.CreateVector(std::vector<int32_t>{0, 1, 2, 3});
    const auto dims_vec = b.CreateVector(dims);
    const auto sparsity_start = b.StartTable();
    b.AddOffset(F(0), traversal);
    b.AddOffset(F(2), dims_vec);
    const auto sparsity = fb::Offset<fb::Table>(b.EndTable(sparsity_start));

    // Tensors: 0 input, 1 w1 fp16, 2 w1 fp32, 3 b1, 4 A, 5 w2 sparse, 6 w2 dense, 7 B.
    struct T {
      std::vector<int32_t> shape;
      int8_t type;
      uint32_t buffer;
      const char* name;
      bool sparse;
    };
    const std::vector<T> tensors = {{{1, 3, 3, 2}, 0, 0, "input", false},  {{2, 1, 1, 2}, 1, 1, "w1_half", false},
                                    {{2, 1, 1, 2}, 0, 0, "w1", false},     {{2}, 0, 2, "b1", false},
                                    {{1, 3, 3, 2}, 0, 0, "A", false},      {{2, 1, 1, 2}, 0, 3, "w2_sparse", true},
                                    {{2, 1, 1, 2}, 0, 0, "w2", false},     {{1, 3, 3, 2}, 0, 0, "B", false}};
    std::vector<fb::Offset<fb::Table>> tensor_offsets;
    for (const T& t : tensors) {
      const auto shape = b.CreateVector(t.shape);
      const auto name = b.CreateString(t.name);
      const auto start = b.StartTable();
      b.AddOffset(F(0), shape);
      b.AddElement<int8_t>(F(1), t.type, 0);
      b.AddElement<uint32_t>(F(2), t.buffer, 0);
      b.AddOffset(F(3), name);
      if (t.sparse) b.AddOffset(F(6), sparsity);
      tensor_offsets.push_back(fb::Offset<fb::Table>(b.EndTable(start)));
    }
    // Operator codes: 0 DEQUANTIZE, 1 CONV_2D (or the replacement), 2 DENSIFY.
    std::vector<fb::Offset<fb::Table>> codes;
    for (int code : {6, op_code, 124}) {
      const auto start = b.StartTable();
      b.AddElement<int8_t>(F(0), static_cast<int8_t>(std::min(code, 127)), 0);
      b.AddElement<int32_t>(F(3), code, 0);
      codes.push_back(fb::Offset<fb::Table>(b.EndTable(start)));
    }
    auto conv_options = [&](int activation) {
      const auto start = b.StartTable();
      b.AddElement<int8_t>(F(0), 1, 0);  // VALID
      b.AddElement<int32_t>(F(1), 1, 0);
      b.AddElement<int32_t>(F(2), 1, 0);
      b.AddElement<int8_t>(F(3), static_cast<int8_t>(activation), 0);
      return fb::Offset<fb::Table>(b.EndTable(start));
    };
    auto op = [&](uint32_t code, std::vector<int32_t> in, std::vector<int32_t> out, fb::Offset<fb::Table> options) {
      const auto ins = b.CreateVector(in);
      const auto outs = b.CreateVector(out);
      const auto start = b.StartTable();
      b.AddElement<uint32_t>(F(0), code, 0);
      b.AddOffset(F(1), ins);
      b.AddOffset(F(2), outs);
      if (!options.IsNull()) {
        b.AddElement<uint8_t>(F(3), 1, 0);  // Conv2DOptions
        b.AddOffset(F(4), options);
      }
      return fb::Offset<fb::Table>(b.EndTable(start));
    };
    std::vector<fb::Offset<fb::Table>> ops;
    ops.push_back(op(0, {1}, {2}, {}));
    ops.push_back(op(1, {0, 2, 3}, {4}, conv_options(3)));
    ops.push_back(op(2, {5}, {6}, {}));
    ops.push_back(op(1, {0, 6, -1}, {7}, conv_options(0)));

    const auto tensors_vec = b.CreateVector(tensor_offsets);
    const auto inputs = b.CreateVector(std::vector<int32_t>{0});
    const auto outputs = b.CreateVector(std::vector<int32_t>{4, 7});
    const auto ops_vec = b.CreateVector(ops);
    const auto graph_start = b.StartTable();
    b.AddOffset(F(0), tensors_vec);
    b.AddOffset(F(1), inputs);
    b.AddOffset(F(2), outputs);
    b.AddOffset(F(3), ops_vec);
    const auto graph = fb::Offset<fb::Table>(b.EndTable(graph_start));

    const auto codes_vec = b.CreateVector(codes);
    const auto graphs_vec = b.CreateVector(std::vector<fb::Offset<fb::Table>>{graph});
    const auto buffers_vec = b.CreateVector(buffers);
    const auto model_start = b.StartTable();
    b.AddElement<uint32_t>(F(0), 3, 0);
    b.AddOffset(F(1), codes_vec);
    b.AddOffset(F(2), graphs_vec);
    b.AddOffset(F(4), buffers_vec);
    b.Finish(fb::Offset<fb::Table>(b.EndTable(model_start)), "TFL3");
    return std::vector<uint8_t>(b.GetBufferPointer(), b.GetBufferPointer() + b.GetSize());
  }
};

std::string Message(const std::vector<uint8_t>& bytes) {
  try {
    pose::ReadTfliteGraph(bytes, "tiny.tflite");
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(TfliteGraph, FoldsHalfAndSparseConstantsWithKnownValues) {
  const TinyModel tiny;
  const pose::TfliteGraph g = pose::ReadTfliteGraph(tiny.Build(), "tiny.tflite");
  // DEQUANTIZE and DENSIFY are folded: two convolutions remain.
  ASSERT_EQ(g.operators.size(), 2u);
  EXPECT_EQ(g.operators[0].activation, pose::TfliteActivation::kRelu6);
  EXPECT_FALSE(g.operators[0].padding_same);
  const pose::TfliteTensor& w1 = g.tensors[g.operators[0].inputs[1]];
  ASSERT_TRUE(w1.constant);
  EXPECT_EQ(w1.values, tiny.w1);  // every value exact in binary16
  const pose::TfliteTensor& w2 = g.tensors[g.operators[1].inputs[1]];
  EXPECT_EQ(w2.values, tiny.w2_dense);  // CSR row 0 → column 1, row 1 → column 0
  EXPECT_EQ(g.operators[1].inputs[2], -1);
}

TEST(TfliteGraph, TinyModelConvertedRunsInOpenCvAsComputedByHand) {
  const TinyModel tiny;
  const pose::TfliteGraph g = pose::ReadTfliteGraph(tiny.Build(), "tiny.tflite");
  const std::string onnx = tools::ConvertTfliteToOnnx(g, "tiny");
  cv::dnn::Net net = cv::dnn::readNetFromONNX(onnx.data(), onnx.size());
  // Input NHWC x[y][x][c] = y + 0.1·x − 0.5·c, fed to ONNX as NCHW.
  int dims[] = {1, 2, 3, 3};
  cv::Mat blob(4, dims, CV_32F);
  for (int c = 0; c < 2; ++c)
    for (int y = 0; y < 3; ++y)
      for (int x = 0; x < 3; ++x) blob.ptr<float>(0, c)[y * 3 + x] = y + 0.1f * x - 0.5f * c;
  net.setInput(blob);
  std::vector<cv::Mat> out;
  net.forward(out, std::vector<cv::String>{"A", "B"});
  ASSERT_EQ(out.size(), 2u);
  for (int y = 0; y < 3; ++y)
    for (int x = 0; x < 3; ++x) {
      const float i0 = y + 0.1f * x, i1 = i0 - 0.5f;
      const float a0 = std::clamp(1.0f * i0 - 2.0f * i1 + 0.25f, 0.0f, 6.0f);
      const float a1 = std::clamp(0.5f * i0 + 3.0f * i1 - 1.0f, 0.0f, 6.0f);
      EXPECT_NEAR(out[0].ptr<float>(0, 0)[y * 3 + x], a0, 1e-5) << y << "," << x;
      EXPECT_NEAR(out[0].ptr<float>(0, 1)[y * 3 + x], a1, 1e-5);
      EXPECT_NEAR(out[1].ptr<float>(0, 0)[y * 3 + x], 5.0f * i1, 1e-5);
      EXPECT_NEAR(out[1].ptr<float>(0, 1)[y * 3 + x], 7.0f * i0, 1e-5);
    }
}

TEST(TfliteGraph, RefusesWhatItCannotReadInOneLine) {
  const std::vector<uint8_t> good = TinyModel().Build();
  // Not a TFLite file.
  std::vector<uint8_t> other = good;
  other[4] = 'X';
  EXPECT_NE(Message(other).find("not a TensorFlow Lite model"), std::string::npos) << Message(other);
  // Truncated anywhere: refused by the verifier (or the identifier check), never a crash.
  for (std::size_t size : {std::size_t(0), std::size_t(7), good.size() / 3, good.size() / 2, good.size() - 9}) {
    const std::vector<uint8_t> cut(good.begin(), good.begin() + static_cast<long>(size));
    const std::string m = Message(cut);
    EXPECT_FALSE(m.empty()) << size;
    EXPECT_EQ(m.find('\n'), std::string::npos);
  }
  // Every single byte flipped: read or refused, never a crash or an exception of another kind.
  int refused = 0;
  for (std::size_t k = 0; k < good.size(); ++k) {
    std::vector<uint8_t> bad = good;
    bad[k] ^= 0xff;
    try {
      pose::ReadTfliteGraph(bad, "tiny.tflite");
    } catch (const InputError&) {
      ++refused;
    }
  }
  EXPECT_GT(refused, 0);
  // An operator Acrolab does not read (SOFTMAX = 25) is named.
  TinyModel softmax;
  softmax.op_code = 25;
  EXPECT_NE(Message(softmax.Build()).find("builtin operator 25"), std::string::npos) << Message(softmax.Build());
}

// ---------------------------------------------------------------------------------------------
// The four BlazePose networks.

struct Network {
  const char* name;
  int size;
  float low, high;  // the input's value range (MediaPipe's preprocessing)
  std::vector<std::string> outputs;  // as scripts/install-models.sh converts it (empty: all)
  bool picture = true;                // a real picture as input, else a synthetic one
};

// The landmark networks' outputs install-models.sh keeps (the segmentation head left out).
const std::vector<std::string> kLandmarkOutputs = {"Identity", "Identity_1", "Identity_3", "Identity_4"};

// The network's input from a real picture: the sample routine's video, frame 150 (the athlete
// in a layout), a 400-pixel square about the athlete resized, in the network's range — so that
// the pose flag is near 1 and the landmarks land on a body.
cv::Mat PictureInput(int size, float low, float high) {
  capture::VideoReader video(testing::SourceDir() / "samples/trials/trampoline_routine/side_camera.mp4");
  const capture::VideoFrame frame = video.Frame(150);
  const cv::Mat rgb(frame.height, frame.width, CV_8UC3, const_cast<std::uint8_t*>(frame.pixels.data()));
  cv::Mat crop;
  cv::resize(rgb(cv::Rect(780, 215, 400, 400)), crop, cv::Size(size, size), 0, 0, cv::INTER_AREA);
  int dims[] = {1, 3, size, size};
  cv::Mat blob(4, dims, CV_32F);
  for (int c = 0; c < 3; ++c)
    for (int y = 0; y < size; ++y)
      for (int x = 0; x < size; ++x)
        blob.ptr<float>(0, c)[y * size + x] = low + (high - low) * crop.at<cv::Vec3b>(y, x)[c] / 255.0f;
  return blob;
}

// A deterministic picture-like input: smooth gradients plus noise, in the network's range.
cv::Mat MakeInput(int size, float low, float high) {
  std::mt19937 rng(20261205);
  std::uniform_real_distribution<float> noise(-0.1f, 0.1f);
  int dims[] = {1, 3, size, size};
  cv::Mat blob(4, dims, CV_32F);
  for (int c = 0; c < 3; ++c)
    for (int y = 0; y < size; ++y)
      for (int x = 0; x < size; ++x) {
        const float t = 0.5f + 0.35f * std::sin(0.05f * x + 0.9f * c) * std::cos(0.04f * y) + noise(rng);
        blob.ptr<float>(0, c)[y * size + x] = low + (high - low) * std::clamp(t, 0.0f, 1.0f);
      }
  return blob;
}

void CheckNetwork(const Network& n) {
  const std::filesystem::path dir = testing::InstalledModelDir();
  const auto tflite = ReadFileBytes(dir / (std::string(n.name) + ".tflite"));
  const pose::TfliteGraph g = pose::ReadTfliteGraph(tflite, n.name);
  const std::string onnx = tools::ConvertTfliteToOnnx(g, n.name, n.outputs);
  // Deterministic, and the bytes install-models.sh pinned (its MANIFEST's hash is checked there;
  // here the installed file is compared whole).
  EXPECT_EQ(onnx, tools::ConvertTfliteToOnnx(g, n.name, n.outputs));
  const auto installed = ReadFileBytes(dir / (std::string(n.name) + ".onnx"));
  EXPECT_TRUE(installed.size() == onnx.size() && std::memcmp(installed.data(), onnx.data(), onnx.size()) == 0)
      << n.name << ": the installed ONNX differs from a fresh conversion";

  const cv::Mat blob = n.picture ? PictureInput(n.size, n.low, n.high) : MakeInput(n.size, n.low, n.high);
  cv::dnn::Net net = cv::dnn::readNetFromONNX(onnx.data(), onnx.size());
  net.setInput(blob);
  std::vector<cv::String> names;
  std::vector<int> kept;
  for (std::size_t k = 0; k < g.outputs.size(); ++k)
    if (n.outputs.empty() || std::count(n.outputs.begin(), n.outputs.end(), g.tensors[g.outputs[k]].name)) {
      names.push_back(g.tensors[g.outputs[k]].name);
      kept.push_back(static_cast<int>(k));
    }
  std::vector<cv::Mat> got;
  net.forward(got, names);

  testing::RefTensor input{{1, n.size, n.size, 3}, {}};
  input.v.resize(static_cast<size_t>(n.size) * n.size * 3);
  for (int y = 0; y < n.size; ++y)
    for (int x = 0; x < n.size; ++x)
      for (int c = 0; c < 3; ++c) input.v[(static_cast<size_t>(y) * n.size + x) * 3 + c] = blob.ptr<float>(0, c)[y * n.size + x];
  const std::vector<testing::RefTensor> all = testing::TfliteReference(g).Run(input);
  std::vector<testing::RefTensor> want;
  for (int k : kept) want.push_back(all[k]);

  ASSERT_EQ(got.size(), want.size());
  for (std::size_t k = 0; k < want.size(); ++k) {
    const testing::RefTensor& w = want[k];
    ASSERT_EQ(static_cast<std::size_t>(got[k].total()), w.v.size()) << names[k];
    // OpenCV's 4-D outputs are NCHW; the reference's NHWC.
    const bool four_d = w.shape.size() == 4;
    double largest = 0, worst = 0;
    for (std::size_t e = 0; e < w.v.size(); ++e) {
      std::size_t at = e;
      if (four_d) {
        const std::size_t c = e % w.shape[3], xy = e / w.shape[3];
        at = c * static_cast<std::size_t>(w.shape[1]) * w.shape[2] + xy;
      }
      largest = std::max(largest, std::abs(w.v[e]));
      worst = std::max(worst, std::abs(static_cast<double>(got[k].ptr<float>()[at]) - w.v[e]));
    }
    const double relative = worst / std::max(largest, 1e-12);
    EXPECT_LE(relative, 1e-3) << n.name << " output " << names[k] << ": largest difference " << worst
                              << " against values up to " << largest;
    ::testing::Test::RecordProperty(std::string(n.name) + "_" + names[k] + "_relative", std::to_string(relative));
    std::printf("%s %s: largest |OpenCV − reference| %.3g of %.3g (relative %.2g)\n", n.name, names[k].c_str(),
                worst, largest, relative);
  }
}

TEST(PoseNetworks, DetectorAgreesWithTheReferenceEvaluation) {
  ACRO_REQUIRE_POSE_MODELS();
  CheckNetwork({"pose_detection", 224, -1.0f, 1.0f, {}});
}
TEST(PoseNetworks, HeavyAgreesOnASyntheticInputToo) {
  ACRO_REQUIRE_POSE_MODELS();
  CheckNetwork({"pose_landmark_heavy", 256, 0.0f, 1.0f, kLandmarkOutputs, false});
}
TEST(PoseNetworks, LiteAgreesWithTheReferenceEvaluation) {
  ACRO_REQUIRE_POSE_MODELS();
  CheckNetwork({"pose_landmark_lite", 256, 0.0f, 1.0f, kLandmarkOutputs});
}
TEST(PoseNetworks, FullAgreesWithTheReferenceEvaluation) {
  ACRO_REQUIRE_POSE_MODELS();
  CheckNetwork({"pose_landmark_full", 256, 0.0f, 1.0f, kLandmarkOutputs});
}
TEST(PoseNetworks, HeavyAgreesWithTheReferenceEvaluation) {
  ACRO_REQUIRE_POSE_MODELS();
  CheckNetwork({"pose_landmark_heavy", 256, 0.0f, 1.0f, kLandmarkOutputs});
}

}  // namespace
}  // namespace acro
