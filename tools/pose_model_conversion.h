#pragma once

// TFLite → ONNX for OpenCV's DNN module (docs/pose.md, "The models"). Debian 12 has no TFLite
// runtime and OpenCV 4.6 reads ONNX but not TFLite, so the BlazePose networks are converted once,
// at install time (scripts/install-models.sh), by this code. The ONNX graph computes in NCHW (as
// OpenCV does): the image input is [1, C, H, W], 4-D tensors stay NCHW and every 4-D output is
// NCHW; a RESHAPE is done in TFLite's NHWC order between two transposes. TF "SAME" padding becomes
// explicit (possibly asymmetric) pads. Opset 11, with one exception: a fused RELU6 is written as
// Clip in the opset-6 attribute form (min, max), the only form OpenCV 4.6's importer takes (4.7
// reads both). The output is the same bytes for the same input.

#include <string>
#include <vector>

#include "acro/pose/tflite_graph.h"

namespace acro::tools {

/// The ONNX model (serialised ModelProto) computing `graph`'s `outputs` (their TFLite names; all
/// when empty) and only the operators they need. Throws acro::InputError naming the graph's source
/// and operator for what has no translation (a layout it cannot follow), or an output it lacks.
std::string ConvertTfliteToOnnx(const pose::TfliteGraph& graph, const std::string& model_name,
                                const std::vector<std::string>& outputs = {});

}  // namespace acro::tools
