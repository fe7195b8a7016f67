#pragma once

/// \file
/// A TensorFlow Lite model read into plain data (docs/pose.md, "The models"): the tensors with their
/// shapes and constant values, the operators in execution order with their options. Only what the
/// BlazePose networks use is accepted; anything else is refused with one line naming the operator.
/// Constants stored as float16 behind DEQUANTIZE, or as a sparse (CSR) tensor behind DENSIFY, are
/// folded into float32 values here, so that a graph holds only operators that compute on the
/// input. The flatbuffer is read by field index (the TFLite schema's declaration order) through
/// flatbuffers' own verifier; nothing of it appears in this header.

#include <cstdint>
#include <span>
#include <string>
#include <vector>

namespace acro::pose {

/// TFLite's BuiltinOperator codes of the operators Acrolab reads (tensorflow/lite/schema/schema.fbs).
enum class TfliteOp : int {
  kAdd = 0,
  kConcatenation = 2,
  kConv2d = 3,
  kDepthwiseConv2d = 4,
  kDepthToSpace = 5,
  kDequantize = 6,
  kLogistic = 14,
  kMaxPool2d = 17,
  kRelu = 19,
  kRelu6 = 21,
  kReshape = 22,
  kResizeBilinear = 23,
  kPad = 34,
  kDensify = 124,
};

/// "CONV_2D" and so on, as TFLite names them.
const char* TfliteOpName(TfliteOp op);

/// A fused activation (TFLite's ActivationFunctionType).
enum class TfliteActivation : int { kNone = 0, kRelu = 1, kRelu6 = 3 };

struct TfliteTensor {
  std::string name;
  std::vector<int> shape;  ///< as stored: NHWC for images
  /// The constant's values (float32, float16 folded, int32 converted exactly); empty for a
  /// tensor computed by the graph.
  std::vector<float> values;
  bool constant = false;

  std::int64_t num_elements() const;
};

struct TfliteOperator {
  TfliteOp op = TfliteOp::kAdd;
  std::vector<int> inputs;   ///< tensor indices; −1 for an optional input left out
  std::vector<int> outputs;  ///< tensor indices
  // Options, where the operator has them.
  bool padding_same = false;  ///< TF "SAME" (else "VALID")
  int stride_w = 1, stride_h = 1;
  int dilation_w = 1, dilation_h = 1;
  int filter_w = 1, filter_h = 1;  ///< pooling
  int depth_multiplier = 1;
  TfliteActivation activation = TfliteActivation::kNone;
  bool align_corners = false, half_pixel_centers = false;
  int axis = 0;        ///< concatenation
  int block_size = 1;  ///< depth to space
};

struct TfliteGraph {
  std::string source;  ///< the file, for messages
  std::vector<TfliteTensor> tensors;
  /// Computing operators in execution order (DEQUANTIZE and DENSIFY of constants folded away).
  std::vector<TfliteOperator> operators;
  std::vector<int> inputs, outputs;  ///< tensor indices
};

/// Reads a TFLite flatbuffer (its first subgraph). Throws acro::InputError naming `source` for a
/// file that is not a TFLite model ("TFL3"), a flatbuffer that fails verification, an operator or
/// tensor type Acrolab does not read, a dangling tensor index, or a constant whose size does not
/// match its shape.
TfliteGraph ReadTfliteGraph(std::span<const std::uint8_t> bytes, const std::string& source);

}  // namespace acro::pose
