#pragma once

// An independent evaluation of a TFLite graph, for the converter's tests: every operator written
// from TFLite's own definition (tensorflow/lite/kernels/*.cc semantics, NHWC, TF "SAME" padding with
// the odd pixel at the end, half-pixel bilinear resizing), in double precision, with plain loops —
// none of the converter's layout bookkeeping and none of OpenCV. Slow and simple on purpose.

#include <algorithm>
#include <cmath>
#include <map>
#include <stdexcept>
#include <vector>

#include "acro/pose/tflite_graph.h"

namespace acro::testing {

struct RefTensor {
  std::vector<int> shape;  // NHWC for 4-D
  std::vector<double> v;
};

class TfliteReference {
 public:
  explicit TfliteReference(const pose::TfliteGraph& graph) : g_(graph) {}

  // Runs the graph on `input` (NHWC, the graph's first input); returns every graph output.
  std::vector<RefTensor> Run(const RefTensor& input) {
    values_.clear();
    values_[g_.inputs[0]] = input;
    for (const pose::TfliteOperator& op : g_.operators) values_[op.outputs[0]] = Eval(op);
    std::vector<RefTensor> out;
    for (int index : g_.outputs) out.push_back(Get(index));
    return out;
  }

 private:
  RefTensor Get(int index) const {
    auto it = values_.find(index);
    if (it != values_.end()) return it->second;
    const pose::TfliteTensor& t = g_.tensors[index];
    if (!t.constant) throw std::logic_error("reference: tensor not computed");
    return {t.shape, std::vector<double>(t.values.begin(), t.values.end())};
  }

  static double Activate(double x, pose::TfliteActivation a) {
    if (a == pose::TfliteActivation::kRelu) return std::max(x, 0.0);
    if (a == pose::TfliteActivation::kRelu6) return std::min(std::max(x, 0.0), 6.0);
    return x;
  }

  // TF's padding: out = ceil(in / stride) for SAME, the extra pixel after.
  static int PadBefore(bool same, int in, int out, int kernel, int stride, int dilation) {
    if (!same) return 0;
    const int total = std::max((out - 1) * stride + (kernel - 1) * dilation + 1 - in, 0);
    return total / 2;
  }

  RefTensor Eval(const pose::TfliteOperator& op) const {
    using pose::TfliteOp;
    const pose::TfliteTensor& out_t = g_.tensors[op.outputs[0]];
    RefTensor out{out_t.shape, std::vector<double>(out_t.num_elements(), 0.0)};
    const RefTensor in = Get(op.inputs[0]);
    auto at4 = [](const RefTensor& t, int n, int y, int x, int c) {
      return t.v[((static_cast<size_t>(n) * t.shape[1] + y) * t.shape[2] + x) * t.shape[3] + c];
    };
    auto ref4 = [](RefTensor& t, int n, int y, int x, int c) -> double& {
      return t.v[((static_cast<size_t>(n) * t.shape[1] + y) * t.shape[2] + x) * t.shape[3] + c];
    };
    switch (op.op) {
      case TfliteOp::kConv2d:
      case TfliteOp::kDepthwiseConv2d: {
        const RefTensor w = Get(op.inputs[1]);
        const bool depthwise = op.op == TfliteOp::kDepthwiseConv2d;
        const int kh = w.shape[1], kw = w.shape[2];
        const int ih = in.shape[1], iw = in.shape[2], ic = in.shape[3];
        const int oh = out.shape[1], ow = out.shape[2], oc = out.shape[3];
        const int pt = PadBefore(op.padding_same, ih, oh, kh, op.stride_h, op.dilation_h);
        const int pl = PadBefore(op.padding_same, iw, ow, kw, op.stride_w, op.dilation_w);
        std::vector<double> bias(oc, 0.0);
        if (op.inputs.size() == 3 && op.inputs[2] >= 0) bias = Get(op.inputs[2]).v;
        for (int y = 0; y < oh; ++y)
          for (int x = 0; x < ow; ++x)
            for (int o = 0; o < oc; ++o) {
              double sum = bias[o];
              for (int ky = 0; ky < kh; ++ky) {
                const int sy = y * op.stride_h - pt + ky * op.dilation_h;
                if (sy < 0 || sy >= ih) continue;
                for (int kx = 0; kx < kw; ++kx) {
                  const int sx = x * op.stride_w - pl + kx * op.dilation_w;
                  if (sx < 0 || sx >= iw) continue;
                  if (depthwise) {
                    // output channel o = input channel · multiplier + m
                    sum += at4(in, 0, sy, sx, o / op.depth_multiplier) *
                           w.v[(static_cast<size_t>(ky) * kw + kx) * oc + o];
                  } else {
                    for (int i = 0; i < ic; ++i)
                      sum += at4(in, 0, sy, sx, i) * w.v[((static_cast<size_t>(o) * kh + ky) * kw + kx) * ic + i];
                  }
                }
              }
              ref4(out, 0, y, x, o) = Activate(sum, op.activation);
            }
        return out;
      }
      case TfliteOp::kMaxPool2d: {
        const int oh = out.shape[1], ow = out.shape[2], c = out.shape[3];
        const int pt = PadBefore(op.padding_same, in.shape[1], oh, op.filter_h, op.stride_h, 1);
        const int pl = PadBefore(op.padding_same, in.shape[2], ow, op.filter_w, op.stride_w, 1);
        for (int y = 0; y < oh; ++y)
          for (int x = 0; x < ow; ++x)
            for (int k = 0; k < c; ++k) {
              double best = -INFINITY;
              for (int ky = 0; ky < op.filter_h; ++ky)
                for (int kx = 0; kx < op.filter_w; ++kx) {
                  const int sy = y * op.stride_h - pt + ky, sx = x * op.stride_w - pl + kx;
                  if (sy >= 0 && sy < in.shape[1] && sx >= 0 && sx < in.shape[2]) best = std::max(best, at4(in, 0, sy, sx, k));
                }
              ref4(out, 0, y, x, k) = Activate(best, op.activation);
            }
        return out;
      }
      case TfliteOp::kAdd: {
        const RefTensor b = Get(op.inputs[1]);
        for (size_t k = 0; k < out.v.size(); ++k)
          out.v[k] = Activate(in.v[k % in.v.size()] + b.v[k % b.v.size()], op.activation);
        return out;
      }
      case TfliteOp::kPad: {
        const RefTensor p = Get(op.inputs[1]);
        const int top = static_cast<int>(p.v[2]), left = static_cast<int>(p.v[4]), front = static_cast<int>(p.v[6]);
        for (int y = 0; y < in.shape[1]; ++y)
          for (int x = 0; x < in.shape[2]; ++x)
            for (int c = 0; c < in.shape[3]; ++c) ref4(out, 0, y + top, x + left, c + front) = at4(in, 0, y, x, c);
        return out;
      }
      case TfliteOp::kResizeBilinear: {
        const int ih = in.shape[1], iw = in.shape[2], oh = out.shape[1], ow = out.shape[2], c = out.shape[3];
        const double sy = static_cast<double>(ih) / oh, sx = static_cast<double>(iw) / ow;
        for (int y = 0; y < oh; ++y) {
          // half-pixel centres: source = (dst + ½)·scale − ½, clamped below at 0
          const double fy = op.half_pixel_centers ? std::max((y + 0.5) * sy - 0.5, 0.0) : y * sy;
          const int y0 = std::min(static_cast<int>(std::floor(fy)), ih - 1), y1 = std::min(y0 + 1, ih - 1);
          const double wy = fy - y0;
          for (int x = 0; x < ow; ++x) {
            const double fx = op.half_pixel_centers ? std::max((x + 0.5) * sx - 0.5, 0.0) : x * sx;
            const int x0 = std::min(static_cast<int>(std::floor(fx)), iw - 1), x1 = std::min(x0 + 1, iw - 1);
            const double wx = fx - x0;
            for (int k = 0; k < c; ++k)
              ref4(out, 0, y, x, k) = (1 - wy) * ((1 - wx) * at4(in, 0, y0, x0, k) + wx * at4(in, 0, y0, x1, k)) +
                                      wy * ((1 - wx) * at4(in, 0, y1, x0, k) + wx * at4(in, 0, y1, x1, k));
          }
        }
        return out;
      }
      case TfliteOp::kReshape:
        out.v = in.v;  // NHWC order is the element order
        return out;
      case TfliteOp::kLogistic:
        for (size_t k = 0; k < out.v.size(); ++k) out.v[k] = 1.0 / (1.0 + std::exp(-in.v[k]));
        return out;
      case TfliteOp::kRelu:
      case TfliteOp::kRelu6:
        for (size_t k = 0; k < out.v.size(); ++k)
          out.v[k] = Activate(in.v[k], op.op == TfliteOp::kRelu ? pose::TfliteActivation::kRelu : pose::TfliteActivation::kRelu6);
        return out;
      case TfliteOp::kConcatenation: {
        const int rank = static_cast<int>(out.shape.size());
        const int axis = op.axis < 0 ? op.axis + rank : op.axis;
        size_t outer = 1, inner = 1;
        for (int d = 0; d < axis; ++d) outer *= out.shape[d];
        for (int d = axis + 1; d < rank; ++d) inner *= out.shape[d];
        size_t offset = 0;
        for (int index : op.inputs) {
          const RefTensor t = Get(index);
          const size_t n = t.shape[axis] * inner;
          for (size_t o = 0; o < outer; ++o)
            std::copy(t.v.begin() + o * n, t.v.begin() + (o + 1) * n, out.v.begin() + o * out.shape[axis] * inner + offset);
          offset += n;
        }
        return out;
      }
      case TfliteOp::kDepthToSpace: {
        const int b = op.block_size, oc = out.shape[3];
        for (int y = 0; y < in.shape[1]; ++y)
          for (int x = 0; x < in.shape[2]; ++x)
            for (int i = 0; i < b; ++i)
              for (int j = 0; j < b; ++j)
                for (int c = 0; c < oc; ++c) ref4(out, 0, y * b + i, x * b + j, c) = at4(in, 0, y, x, (i * b + j) * oc + c);
        return out;
      }
      default:
        throw std::logic_error(std::string("reference: no ") + pose::TfliteOpName(op.op));
    }
  }

  const pose::TfliteGraph& g_;
  std::map<int, RefTensor> values_;
};

}  // namespace acro::testing
