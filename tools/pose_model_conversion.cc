#include "pose_model_conversion.h"

#include <algorithm>
#include <cstring>

#include <fmt/format.h>
#include <onnx/onnx_pb.h>

#include "acro/base/input_error.h"

namespace acro::tools {
namespace {

using pose::TfliteActivation;
using pose::TfliteGraph;
using pose::TfliteOp;
using pose::TfliteOperator;
using pose::TfliteTensor;

// How a computed tensor is laid out in the ONNX graph: a 4-D TFLite tensor (NHWC) is kept NCHW;
// any other rank keeps TFLite's order.
enum class Layout { kNchw, kPlain };

// NHWC axis → NCHW axis.
int NchwAxis(int nhwc_axis) {
  static constexpr int kMap[4] = {0, 2, 3, 1};
  return kMap[nhwc_axis];
}

class Exporter {
 public:
  Exporter(const TfliteGraph& graph, const std::vector<std::string>& keep)
      : g_(graph), layout_(graph.tensors.size(), Layout::kPlain) {
    // The outputs kept (all when none is named), and the operators they need.
    for (int index : g_.outputs)
      if (keep.empty() || std::count(keep.begin(), keep.end(), g_.tensors[index].name)) outputs_.push_back(index);
    for (const std::string& name : keep)
      if (std::none_of(outputs_.begin(), outputs_.end(), [&](int i) { return g_.tensors[i].name == name; }))
        throw InputError(g_.source, "outputs", fmt::format("no graph output named '{}'", name));
    std::vector<bool> needed(g_.tensors.size(), false);
    for (int index : outputs_) needed[index] = true;
    used_.assign(g_.operators.size(), false);
    for (std::size_t k = g_.operators.size(); k-- > 0;) {
      if (!needed[g_.operators[k].outputs[0]]) continue;
      used_[k] = true;
      for (int in : g_.operators[k].inputs)
        if (in >= 0) needed[in] = true;
    }
  }

  std::string Run(const std::string& model_name) {
    onnx::ModelProto model;
    model.set_ir_version(7);
    model.set_producer_name("acrolab");
    model.set_producer_version("tflite-to-onnx 1");
    model.set_model_version(1);
    auto* opset = model.add_opset_import();
    opset->set_domain("");
    opset->set_version(11);
    graph_ = model.mutable_graph();
    graph_->set_name(model_name);

    for (int index : g_.inputs) AddInput(index);
    for (std::size_t k = 0; k < g_.operators.size(); ++k)
      if (used_[k]) Translate(static_cast<int>(k), g_.operators[k]);
    for (int index : outputs_) AddOutput(index);

    std::string bytes;
    if (!model.SerializeToString(&bytes))
      throw InputError(g_.source, "", "the ONNX model could not be serialised");
    return bytes;
  }

 private:
  [[noreturn]] void Fail(int number, const std::string& problem) const {
    throw InputError(g_.source, fmt::format("operator {}", number), problem);
  }

  // Value names: the graph's inputs and outputs keep their TFLite names (the detector asks for
  // them); every other tensor is "t<index>".
  std::string Name(int index) const {
    const bool boundary = std::count(g_.inputs.begin(), g_.inputs.end(), index) ||
                          std::count(outputs_.begin(), outputs_.end(), index);
    return boundary ? g_.tensors[index].name : fmt::format("t{}", index);
  }

  std::string Fresh(const std::string& stem) { return fmt::format("{}_{}", stem, counter_++); }

  static void SetShape(onnx::ValueInfoProto* info, const std::vector<int64_t>& shape) {
    auto* tensor_type = info->mutable_type()->mutable_tensor_type();
    tensor_type->set_elem_type(onnx::TensorProto::FLOAT);
    auto* dims = tensor_type->mutable_shape();
    for (int64_t d : shape) dims->add_dim()->set_dim_value(d);
  }

  // The ONNX shape of a TFLite tensor in the layout it has in the graph.
  std::vector<int64_t> OnnxShape(int index) const {
    const std::vector<int>& s = g_.tensors[index].shape;
    if (layout_[index] == Layout::kNchw) return {s[0], s[3], s[1], s[2]};
    return std::vector<int64_t>(s.begin(), s.end());
  }

  void AddInput(int index) {
    if (g_.tensors[index].shape.size() == 4) layout_[index] = Layout::kNchw;
    auto* info = graph_->add_input();
    info->set_name(Name(index));
    SetShape(info, OnnxShape(index));
  }

  void AddOutput(int index) {
    auto* info = graph_->add_output();
    info->set_name(Name(index));
    SetShape(info, OnnxShape(index));
  }

  // An initialiser of float values (raw little-endian bytes: compact and deterministic).
  std::string Constant(const std::string& stem, const std::vector<int64_t>& dims, const std::vector<float>& values) {
    onnx::TensorProto* t = graph_->add_initializer();
    const std::string name = Fresh(stem);
    t->set_name(name);
    t->set_data_type(onnx::TensorProto::FLOAT);
    for (int64_t d : dims) t->add_dims(d);
    t->set_raw_data(std::string(reinterpret_cast<const char*>(values.data()), values.size() * sizeof(float)));
    return name;
  }

  std::string IntConstant(const std::string& stem, const std::vector<int64_t>& values) {
    onnx::TensorProto* t = graph_->add_initializer();
    const std::string name = Fresh(stem);
    t->set_name(name);
    t->set_data_type(onnx::TensorProto::INT64);
    t->add_dims(static_cast<int64_t>(values.size()));
    t->set_raw_data(std::string(reinterpret_cast<const char*>(values.data()), values.size() * sizeof(int64_t)));
    return name;
  }

  onnx::NodeProto* Node(const std::string& type, const std::vector<std::string>& inputs, const std::string& output) {
    onnx::NodeProto* node = graph_->add_node();
    node->set_op_type(type);
    node->set_name(output);
    for (const std::string& in : inputs) node->add_input(in);
    node->add_output(output);
    return node;
  }

  static void Ints(onnx::NodeProto* node, const std::string& name, const std::vector<int64_t>& values) {
    auto* a = node->add_attribute();
    a->set_name(name);
    a->set_type(onnx::AttributeProto::INTS);
    for (int64_t v : values) a->add_ints(v);
  }
  static void Int(onnx::NodeProto* node, const std::string& name, int64_t value) {
    auto* a = node->add_attribute();
    a->set_name(name);
    a->set_type(onnx::AttributeProto::INT);
    a->set_i(value);
  }
  static void Float(onnx::NodeProto* node, const std::string& name, float value) {
    auto* a = node->add_attribute();
    a->set_name(name);
    a->set_type(onnx::AttributeProto::FLOAT);
    a->set_f(value);
  }
  static void String(onnx::NodeProto* node, const std::string& name, const std::string& value) {
    auto* a = node->add_attribute();
    a->set_name(name);
    a->set_type(onnx::AttributeProto::STRING);
    a->set_s(value);
  }

  // The node computing `op` writes `raw`; a fused activation follows it and writes `final`.
  std::string OutputBeforeActivation(const TfliteOperator& op) {
    return op.activation == TfliteActivation::kNone ? Name(op.outputs[0]) : Fresh("preact");
  }
  void Activate(const TfliteOperator& op, const std::string& raw) {
    const std::string out = Name(op.outputs[0]);
    if (op.activation == TfliteActivation::kRelu) {
      Node("Relu", {raw}, out);
    } else if (op.activation == TfliteActivation::kRelu6) {
      onnx::NodeProto* clip = Node("Clip", {raw}, out);
      Float(clip, "min", 0.0f);
      Float(clip, "max", 6.0f);
    }
  }

  // TF's padding of a window: "VALID" none; "SAME" so that out = ceil(in / stride), the odd pixel
  // at the end (tensorflow/lite/kernels/padding.h).
  static std::pair<int64_t, int64_t> SamePads(int in, int kernel, int stride, int dilation) {
    const int effective = (kernel - 1) * dilation + 1;
    const int out = (in + stride - 1) / stride;
    const int total = std::max((out - 1) * stride + effective - in, 0);
    return {total / 2, total - total / 2};
  }
  std::vector<int64_t> Pads(const TfliteOperator& op, int input, int kernel_h, int kernel_w) const {
    if (!op.padding_same) return {0, 0, 0, 0};
    const std::vector<int>& s = g_.tensors[input].shape;
    const auto [top, bottom] = SamePads(s[1], kernel_h, op.stride_h, op.dilation_h);
    const auto [left, right] = SamePads(s[2], kernel_w, op.stride_w, op.dilation_w);
    return {top, left, bottom, right};
  }

  // The input as the node needs it: NCHW for 4-D work.
  std::string AsNchw(int number, int index) {
    if (g_.tensors[index].constant) Fail(number, fmt::format("a constant 4-D input {} is not read", index));
    if (layout_[index] != Layout::kNchw) Fail(number, fmt::format("tensor {} is not 4-D", index));
    return Name(index);
  }

  void Convolution(int number, const TfliteOperator& op) {
    const TfliteTensor& filter = g_.tensors[op.inputs[1]];
    const int input = op.inputs[0];
    const int kh = filter.shape[1], kw = filter.shape[2];
    const int channels_in = g_.tensors[input].shape[3];
    const int channels_out = g_.tensors[op.outputs[0]].shape[3];
    const bool depthwise = op.op == TfliteOp::kDepthwiseConv2d;
    // Filters: CONV_2D [O, KH, KW, I] and DEPTHWISE_CONV_2D [1, KH, KW, C·M] → ONNX [O, I/group, KH, KW].
    const int per_group_in = depthwise ? 1 : filter.shape[3];
    if (depthwise ? filter.shape[3] != channels_out || channels_out != channels_in * op.depth_multiplier
                  : filter.shape[0] != channels_out || filter.shape[3] != channels_in)
      Fail(number, fmt::format("filter [{}] for {} → {} channels", fmt::join(filter.shape, ", "),
                               channels_in, channels_out));
    std::vector<float> weights(static_cast<std::size_t>(channels_out) * per_group_in * kh * kw);
    for (int o = 0; o < channels_out; ++o)
      for (int i = 0; i < per_group_in; ++i)
        for (int y = 0; y < kh; ++y)
          for (int x = 0; x < kw; ++x) {
            const std::size_t from = depthwise
                                         ? (static_cast<std::size_t>(y) * kw + x) * channels_out + o
                                         : ((static_cast<std::size_t>(o) * kh + y) * kw + x) * per_group_in + i;
            weights[((static_cast<std::size_t>(o) * per_group_in + i) * kh + y) * kw + x] = filter.values[from];
          }
    std::vector<float> bias(channels_out, 0.0f);
    if (op.inputs.size() == 3 && op.inputs[2] != -1) {
      const TfliteTensor& b = g_.tensors[op.inputs[2]];
      if (!b.constant) Fail(number, "a computed bias");
      bias = b.values;
    }
    const std::string w = Constant("weight", {channels_out, per_group_in, kh, kw}, weights);
    const std::string bn = Constant("bias", {channels_out}, bias);
    const std::string raw = OutputBeforeActivation(op);
    onnx::NodeProto* node = Node("Conv", {AsNchw(number, input), w, bn}, raw);
    Ints(node, "kernel_shape", {kh, kw});
    Ints(node, "strides", {op.stride_h, op.stride_w});
    Ints(node, "dilations", {op.dilation_h, op.dilation_w});
    Ints(node, "pads", Pads(op, input, kh, kw));
    Int(node, "group", depthwise ? channels_in : 1);
    Activate(op, raw);
  }

  void MaxPool(int number, const TfliteOperator& op) {
    const std::string raw = OutputBeforeActivation(op);
    onnx::NodeProto* node = Node("MaxPool", {AsNchw(number, op.inputs[0])}, raw);
    Ints(node, "kernel_shape", {op.filter_h, op.filter_w});
    Ints(node, "strides", {op.stride_h, op.stride_w});
    Ints(node, "pads", Pads(op, op.inputs[0], op.filter_h, op.filter_w));
    Activate(op, raw);
  }

  // ADD of two computed tensors of one layout, or of a computed tensor and a constant broadcast
  // along the channels.
  void Add(int number, const TfliteOperator& op) {
    std::vector<std::string> names;
    const int out = op.outputs[0];
    for (int index : op.inputs) {
      const TfliteTensor& t = g_.tensors[index];
      if (!t.constant) {
        if (layout_[index] != layout_[out]) Fail(number, "ADD of tensors of different ranks");
        names.push_back(Name(index));
        continue;
      }
      std::vector<int64_t> dims(t.shape.begin(), t.shape.end());
      if (layout_[out] == Layout::kNchw) {
        const int channels = g_.tensors[out].shape[3];
        if (t.num_elements() == 1)
          dims = {1};
        else if (t.num_elements() == channels && (t.shape.size() == 1 || t.shape.size() == 4))
          dims = {1, channels, 1, 1};
        else
          Fail(number, fmt::format("ADD of a constant of shape [{}]", fmt::join(t.shape, ", ")));
      }
      names.push_back(Constant("addend", dims, t.values));
    }
    const std::string raw = OutputBeforeActivation(op);
    Node("Add", names, raw);
    Activate(op, raw);
  }

  void Pad(int number, const TfliteOperator& op) {
    const TfliteTensor& paddings = g_.tensors[op.inputs[1]];
    const int rank = static_cast<int>(g_.tensors[op.inputs[0]].shape.size());
    if (rank != 4 || paddings.num_elements() != 8) Fail(number, "PAD of a tensor that is not 4-D");
    // TFLite [[n0, n1], [h0, h1], [w0, w1], [c0, c1]] → ONNX [n0, c0, h0, w0, n1, c1, h1, w1].
    std::vector<int64_t> pads(8);
    for (int axis = 0; axis < 4; ++axis) {
      pads[NchwAxis(axis)] = static_cast<int64_t>(paddings.values[2 * axis]);
      pads[4 + NchwAxis(axis)] = static_cast<int64_t>(paddings.values[2 * axis + 1]);
    }
    onnx::NodeProto* node = Node("Pad", {AsNchw(number, op.inputs[0]), IntConstant("pads", pads)}, Name(op.outputs[0]));
    String(node, "mode", "constant");
  }

  void Resize(int number, const TfliteOperator& op) {
    const int input = op.inputs[0];
    const std::vector<int>& in = g_.tensors[input].shape;
    const std::vector<int>& out = g_.tensors[op.outputs[0]].shape;
    const TfliteTensor& size = g_.tensors[op.inputs[1]];
    if (size.num_elements() != 2 || size.values[0] != out[1] || size.values[1] != out[2])
      Fail(number, "RESIZE_BILINEAR whose size disagrees with its output");
    const std::vector<float> scales = {1.0f, 1.0f, static_cast<float>(out[1]) / in[1],
                                       static_cast<float>(out[2]) / in[2]};
    onnx::NodeProto* node = Node("Resize",
                                 {AsNchw(number, input), Constant("roi", {0}, {}), Constant("scales", {4}, scales)},
                                 Name(op.outputs[0]));
    String(node, "mode", "linear");
    String(node, "coordinate_transformation_mode",
           op.align_corners ? "align_corners" : op.half_pixel_centers ? "half_pixel" : "asymmetric");
  }

  // RESHAPE follows TFLite's element order: a 4-D input goes back to NHWC first, and a 4-D
  // result comes forward to NCHW.
  void Reshape(int number, const TfliteOperator& op) {
    const int input = op.inputs[0], out = op.outputs[0];
    std::string data = Name(input);
    if (g_.tensors[input].constant) Fail(number, "RESHAPE of a constant");
    if (layout_[input] == Layout::kNchw) {
      const std::string nhwc = Fresh("nhwc");
      Ints(Node("Transpose", {data}, nhwc), "perm", {0, 2, 3, 1});
      data = nhwc;
    }
    const std::vector<int>& shape = g_.tensors[out].shape;
    const bool four_d = shape.size() == 4;
    const std::string reshaped = four_d ? Fresh("reshaped") : Name(out);
    Node("Reshape", {data, IntConstant("shape", std::vector<int64_t>(shape.begin(), shape.end()))}, reshaped);
    if (four_d) {
      Ints(Node("Transpose", {reshaped}, Name(out)), "perm", {0, 3, 1, 2});
      layout_[out] = Layout::kNchw;
    }
  }

  void Concatenation(int number, const TfliteOperator& op) {
    const int out = op.outputs[0];
    const int rank = static_cast<int>(g_.tensors[out].shape.size());
    int axis = op.axis < 0 ? op.axis + rank : op.axis;
    if (axis < 0 || axis >= rank) Fail(number, fmt::format("concatenation axis {}", op.axis));
    std::vector<std::string> names;
    for (int index : op.inputs) {
      if (g_.tensors[index].constant || layout_[index] != layout_[out])
        Fail(number, "CONCATENATION of a constant or of tensors of different ranks");
      names.push_back(Name(index));
    }
    if (layout_[out] == Layout::kNchw) axis = NchwAxis(axis);
    const std::string raw = OutputBeforeActivation(op);
    Int(Node("Concat", names, raw), "axis", axis);
    Activate(op, raw);
  }

  void Translate(int number, const TfliteOperator& op) {
    const int out = op.outputs[0];
    // 4-D results are NCHW unless RESHAPE decides otherwise.
    layout_[out] = g_.tensors[out].shape.size() == 4 ? Layout::kNchw : Layout::kPlain;
    switch (op.op) {
      case TfliteOp::kConv2d:
      case TfliteOp::kDepthwiseConv2d: Convolution(number, op); break;
      case TfliteOp::kMaxPool2d: MaxPool(number, op); break;
      case TfliteOp::kAdd: Add(number, op); break;
      case TfliteOp::kPad: Pad(number, op); break;
      case TfliteOp::kResizeBilinear: Resize(number, op); break;
      case TfliteOp::kReshape: Reshape(number, op); break;
      case TfliteOp::kConcatenation: Concatenation(number, op); break;
      case TfliteOp::kLogistic: Node("Sigmoid", {Name(op.inputs[0])}, Name(out)); break;
      case TfliteOp::kRelu: Node("Relu", {Name(op.inputs[0])}, Name(out)); break;
      case TfliteOp::kRelu6: {
        onnx::NodeProto* clip = Node("Clip", {Name(op.inputs[0])}, Name(out));
        Float(clip, "min", 0.0f);
        Float(clip, "max", 6.0f);
        break;
      }
      case TfliteOp::kDepthToSpace: {
        onnx::NodeProto* node = Node("DepthToSpace", {AsNchw(number, op.inputs[0])}, Name(out));
        Int(node, "blocksize", op.block_size);
        String(node, "mode", "DCR");  // TFLite's order: (block row, block column, channel)
        break;
      }
      default:
        Fail(number, fmt::format("{} has no translation", pose::TfliteOpName(op.op)));
    }
    if (layout_[out] == Layout::kNchw && layout_[op.inputs[0]] != Layout::kNchw && op.op != TfliteOp::kReshape)
      Fail(number, "a 4-D result of a tensor that is not 4-D");
  }

  const TfliteGraph& g_;
  std::vector<int> outputs_;
  std::vector<bool> used_;
  std::vector<Layout> layout_;
  onnx::GraphProto* graph_ = nullptr;
  int counter_ = 0;
};

}  // namespace

std::string ConvertTfliteToOnnx(const pose::TfliteGraph& graph, const std::string& model_name,
                                const std::vector<std::string>& outputs) {
  return Exporter(graph, outputs).Run(model_name);
}

}  // namespace acro::tools
