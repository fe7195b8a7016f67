#include "acro/pose/tflite_graph.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <map>
#include <optional>

#include <flatbuffers/flatbuffers.h>
#include <fmt/format.h>

#include "acro/base/input_error.h"

namespace acro::pose {
namespace {

// The TFLite schema (tensorflow/lite/schema/schema.fbs, version 3) read by field index: a field's
// vtable offset is 4 + 2 × its declaration index, deprecated fields counted.
constexpr flatbuffers::voffset_t Field(int index) {
  return static_cast<flatbuffers::voffset_t>(4 + 2 * index);
}

// Model
constexpr auto kModelOperatorCodes = Field(1), kModelSubgraphs = Field(2), kModelBuffers = Field(4);
// OperatorCode
constexpr auto kCodeDeprecatedBuiltin = Field(0), kCodeCustom = Field(1), kCodeBuiltin = Field(3);
// SubGraph
constexpr auto kGraphTensors = Field(0), kGraphInputs = Field(1), kGraphOutputs = Field(2),
               kGraphOperators = Field(3);
// Tensor
constexpr auto kTensorShape = Field(0), kTensorType = Field(1), kTensorBuffer = Field(2),
               kTensorName = Field(3), kTensorSparsity = Field(6);
// Buffer
constexpr auto kBufferData = Field(0), kBufferOffset = Field(1);
// Operator
constexpr auto kOpCodeIndex = Field(0), kOpInputs = Field(1), kOpOutputs = Field(2),
               kOpOptionsType = Field(3), kOpOptions = Field(4);
// SparsityParameters and DimensionMetadata
constexpr auto kSparseTraversal = Field(0), kSparseBlockMap = Field(1), kSparseDims = Field(2);
constexpr auto kDimFormat = Field(0), kDimDenseSize = Field(1), kDimSegmentsType = Field(2),
               kDimSegments = Field(3), kDimIndicesType = Field(4), kDimIndices = Field(5);

// TensorType
constexpr int kFloat32 = 0, kFloat16 = 1, kInt32 = 2;
// BuiltinOptions union members (schema order, NONE = 0).
constexpr int kConv2dOptions = 1, kDepthwiseOptions = 2, kPool2dOptions = 5,
              kConcatenationOptions = 10, kAddOptions = 11, kResizeBilinearOptions = 15,
              kReshapeOptions = 17, kDepthToSpaceOptions = 94;
// SparseIndexVector union members.
constexpr int kInt32Vector = 1, kUint16Vector = 2, kUint8Vector = 3;

using flatbuffers::Offset;
using flatbuffers::String;
using flatbuffers::Table;
using flatbuffers::Vector;
using flatbuffers::Verifier;

template <typename T>
const Vector<T>* VectorField(const Table* table, flatbuffers::voffset_t field) {
  return table->GetPointer<const Vector<T>*>(field);
}
const Vector<Offset<Table>>* TablesField(const Table* table, flatbuffers::voffset_t field) {
  return table->GetPointer<const Vector<Offset<Table>>*>(field);
}

// ---------------------------------------------------------------------------------------------
// Verification: each table's fields are checked where the schema puts them (what flatc's
// generated Verify() does), so that every later read stays inside the buffer.

bool VerifyIntVector(const Table* t, Verifier& v, flatbuffers::voffset_t field) {
  return t->VerifyOffset(v, field) && v.VerifyVector(VectorField<int32_t>(t, field));
}

bool VerifyIndexVector(const Table* t, Verifier& v, flatbuffers::voffset_t type_field,
                       flatbuffers::voffset_t field) {
  if (!t->VerifyField<uint8_t>(v, type_field, 1) || !t->VerifyOffset(v, field)) return false;
  const Table* vec = t->GetPointer<const Table*>(field);
  if (vec == nullptr) return true;
  if (!vec->VerifyTableStart(v) || !vec->VerifyOffset(v, Field(0))) return false;
  bool ok = true;
  switch (t->GetField<uint8_t>(type_field, 0)) {
    case kInt32Vector: ok = v.VerifyVector(VectorField<int32_t>(vec, Field(0))); break;
    case kUint16Vector: ok = v.VerifyVector(VectorField<uint16_t>(vec, Field(0))); break;
    case kUint8Vector: ok = v.VerifyVector(VectorField<uint8_t>(vec, Field(0))); break;
    default: ok = false;
  }
  return ok && v.EndTable();
}

bool VerifySparsity(const Table* t, Verifier& v) {
  if (!t->VerifyTableStart(v) || !VerifyIntVector(t, v, kSparseTraversal) ||
      !VerifyIntVector(t, v, kSparseBlockMap) || !t->VerifyOffset(v, kSparseDims))
    return false;
  const auto* dims = TablesField(t, kSparseDims);
  if (dims != nullptr) {
    if (!v.VerifyVector(dims)) return false;
    for (const Table* d : *dims) {
      if (!d->VerifyTableStart(v) || !d->VerifyField<int8_t>(v, kDimFormat, 1) ||
          !d->VerifyField<int32_t>(v, kDimDenseSize, 4) ||
          !VerifyIndexVector(d, v, kDimSegmentsType, kDimSegments) ||
          !VerifyIndexVector(d, v, kDimIndicesType, kDimIndices) || !v.EndTable())
        return false;
    }
  }
  return v.EndTable();
}

bool VerifyTensor(const Table* t, Verifier& v) {
  if (!t->VerifyTableStart(v) || !VerifyIntVector(t, v, kTensorShape) ||
      !t->VerifyField<int8_t>(v, kTensorType, 1) || !t->VerifyField<uint32_t>(v, kTensorBuffer, 4) ||
      !t->VerifyOffset(v, kTensorName) || !v.VerifyString(t->GetPointer<const String*>(kTensorName)) ||
      !t->VerifyOffset(v, kTensorSparsity))
    return false;
  const Table* sparsity = t->GetPointer<const Table*>(kTensorSparsity);
  if (sparsity != nullptr && !VerifySparsity(sparsity, v)) return false;
  return v.EndTable();
}

// An options table: every field of the tables Acrolab reads is a 4-byte integer or a 1-byte
// enum or bool, and ReshapeOptions' new_shape a vector; the reader asks only for those.
bool VerifyOptions(const Table* t, Verifier& v, int type) {
  if (!t->VerifyTableStart(v)) return false;
  bool ok = true;
  switch (type) {
    case kConv2dOptions:  // padding, stride_w, stride_h, activation, dilation_w, dilation_h
      ok = t->VerifyField<int8_t>(v, Field(0), 1) && t->VerifyField<int32_t>(v, Field(1), 4) &&
           t->VerifyField<int32_t>(v, Field(2), 4) && t->VerifyField<int8_t>(v, Field(3), 1) &&
           t->VerifyField<int32_t>(v, Field(4), 4) && t->VerifyField<int32_t>(v, Field(5), 4);
      break;
    case kDepthwiseOptions:  // padding, stride_w, stride_h, multiplier, activation, dilations
      ok = t->VerifyField<int8_t>(v, Field(0), 1) && t->VerifyField<int32_t>(v, Field(1), 4) &&
           t->VerifyField<int32_t>(v, Field(2), 4) && t->VerifyField<int32_t>(v, Field(3), 4) &&
           t->VerifyField<int8_t>(v, Field(4), 1) && t->VerifyField<int32_t>(v, Field(5), 4) &&
           t->VerifyField<int32_t>(v, Field(6), 4);
      break;
    case kPool2dOptions:  // padding, stride_w, stride_h, filter_w, filter_h, activation
      ok = t->VerifyField<int8_t>(v, Field(0), 1) && t->VerifyField<int32_t>(v, Field(1), 4) &&
           t->VerifyField<int32_t>(v, Field(2), 4) && t->VerifyField<int32_t>(v, Field(3), 4) &&
           t->VerifyField<int32_t>(v, Field(4), 4) && t->VerifyField<int8_t>(v, Field(5), 1);
      break;
    case kConcatenationOptions:  // axis, activation
      ok = t->VerifyField<int32_t>(v, Field(0), 4) && t->VerifyField<int8_t>(v, Field(1), 1);
      break;
    case kAddOptions:  // activation
      ok = t->VerifyField<int8_t>(v, Field(0), 1);
      break;
    case kResizeBilinearOptions:  // (new_height, new_width deprecated), align, half pixel
      ok = t->VerifyField<uint8_t>(v, Field(2), 1) && t->VerifyField<uint8_t>(v, Field(3), 1);
      break;
    case kReshapeOptions:
      ok = VerifyIntVector(t, v, Field(0));
      break;
    case kDepthToSpaceOptions:
      ok = t->VerifyField<int32_t>(v, Field(0), 4);
      break;
    default:
      break;  // options Acrolab does not read are not looked at
  }
  return ok && v.EndTable();
}

bool VerifyOperator(const Table* t, Verifier& v) {
  if (!t->VerifyTableStart(v) || !t->VerifyField<uint32_t>(v, kOpCodeIndex, 4) ||
      !VerifyIntVector(t, v, kOpInputs) || !VerifyIntVector(t, v, kOpOutputs) ||
      !t->VerifyField<uint8_t>(v, kOpOptionsType, 1) || !t->VerifyOffset(v, kOpOptions))
    return false;
  const Table* options = t->GetPointer<const Table*>(kOpOptions);
  if (options != nullptr && !VerifyOptions(options, v, t->GetField<uint8_t>(kOpOptionsType, 0)))
    return false;
  return v.EndTable();
}

bool VerifySubgraph(const Table* t, Verifier& v) {
  if (!t->VerifyTableStart(v) || !t->VerifyOffset(v, kGraphTensors) ||
      !VerifyIntVector(t, v, kGraphInputs) || !VerifyIntVector(t, v, kGraphOutputs) ||
      !t->VerifyOffset(v, kGraphOperators))
    return false;
  const auto* tensors = TablesField(t, kGraphTensors);
  const auto* ops = TablesField(t, kGraphOperators);
  if (tensors == nullptr || ops == nullptr || !v.VerifyVector(tensors) || !v.VerifyVector(ops))
    return false;
  for (const Table* tensor : *tensors)
    if (!VerifyTensor(tensor, v)) return false;
  for (const Table* op : *ops)
    if (!VerifyOperator(op, v)) return false;
  return v.EndTable();
}

bool VerifyModel(const Table* t, Verifier& v) {
  if (!t->VerifyTableStart(v) || !t->VerifyOffset(v, kModelOperatorCodes) ||
      !t->VerifyOffset(v, kModelSubgraphs) || !t->VerifyOffset(v, kModelBuffers))
    return false;
  const auto* codes = TablesField(t, kModelOperatorCodes);
  const auto* graphs = TablesField(t, kModelSubgraphs);
  const auto* buffers = TablesField(t, kModelBuffers);
  if (codes == nullptr || graphs == nullptr || buffers == nullptr || !v.VerifyVector(codes) ||
      !v.VerifyVector(graphs) || !v.VerifyVector(buffers) || graphs->size() == 0)
    return false;
  for (const Table* code : *codes) {
    if (!code->VerifyTableStart(v) || !code->VerifyField<int8_t>(v, kCodeDeprecatedBuiltin, 1) ||
        !code->VerifyOffset(v, kCodeCustom) || !code->VerifyField<int32_t>(v, kCodeBuiltin, 4) ||
        !v.EndTable())
      return false;
  }
  for (const Table* buffer : *buffers) {
    if (!buffer->VerifyTableStart(v) || !buffer->VerifyOffset(v, kBufferData) ||
        !v.VerifyVector(VectorField<uint8_t>(buffer, kBufferData)) ||
        !buffer->VerifyField<uint64_t>(v, kBufferOffset, 8) || !v.EndTable())
      return false;
  }
  // The first subgraph is the model; the others (none in BlazePose) are not read.
  if (!VerifySubgraph(graphs->Get(0), v)) return false;
  return v.EndTable();
}

// ---------------------------------------------------------------------------------------------
// Values.

// IEEE 754 binary16 → binary32, exactly (subnormals, infinities and NaN included).
float HalfToFloat(uint16_t h) {
  const uint32_t sign = (h >> 15) & 1u, exponent = (h >> 10) & 0x1fu, mantissa = h & 0x3ffu;
  float magnitude;
  if (exponent == 0)
    magnitude = std::ldexp(static_cast<float>(mantissa), -24);
  else if (exponent == 31)
    magnitude = mantissa == 0 ? std::numeric_limits<float>::infinity()
                              : std::numeric_limits<float>::quiet_NaN();
  else
    magnitude = std::ldexp(static_cast<float>(mantissa | 0x400u), static_cast<int>(exponent) - 25);
  return sign ? -magnitude : magnitude;
}

std::vector<int> ReadInts(const Vector<int32_t>* vec) {
  std::vector<int> out;
  if (vec == nullptr) return out;
  out.reserve(vec->size());
  for (int32_t x : *vec) out.push_back(x);
  return out;
}

class GraphReader {
 public:
  GraphReader(const Table* model, std::string source) : model_(model), source_(std::move(source)) {}

  TfliteGraph Read() {
    const Table* graph = TablesField(model_, kModelSubgraphs)->Get(0);
    const auto* tensors = TablesField(graph, kGraphTensors);
    result_.source = source_;
    tensor_types_.resize(tensors->size());
    sparse_.resize(tensors->size(), nullptr);
    raw_.resize(tensors->size());
    for (flatbuffers::uoffset_t i = 0; i < tensors->size(); ++i) ReadTensor(i, tensors->Get(i));
    result_.inputs = ReadInts(VectorField<int32_t>(graph, kGraphInputs));
    result_.outputs = ReadInts(VectorField<int32_t>(graph, kGraphOutputs));
    for (int index : result_.inputs) CheckIndex(index, "graph input");
    for (int index : result_.outputs) CheckIndex(index, "graph output");
    const auto* ops = TablesField(graph, kGraphOperators);
    for (flatbuffers::uoffset_t i = 0; i < ops->size(); ++i) ReadOperator(static_cast<int>(i), ops->Get(i));
    for (int index : result_.outputs)
      if (!computed_.count(index) && !result_.tensors[index].constant)
        Fail("graph output", fmt::format("tensor {} is never computed", index));
    return std::move(result_);
  }

 private:
  [[noreturn]] void Fail(const std::string& where, const std::string& problem) const {
    throw InputError(source_, where, problem);
  }

  void CheckIndex(int index, const std::string& where) const {
    if (index < 0 || index >= static_cast<int>(result_.tensors.size()))
      Fail(where, fmt::format("tensor index {} outside the {} tensors", index,
                              result_.tensors.size()));
  }

  void ReadTensor(flatbuffers::uoffset_t i, const Table* t) {
    TfliteTensor tensor;
    const auto* name = t->GetPointer<const String*>(kTensorName);
    if (name != nullptr) tensor.name = name->str();
    tensor.shape = ReadInts(VectorField<int32_t>(t, kTensorShape));
    const std::string where = fmt::format("tensor {} ({})", i, tensor.name);
    for (int d : tensor.shape)
      if (d < 0 || d > (1 << 24)) Fail(where, fmt::format("dimension {} out of range", d));
    if (tensor.num_elements() > (std::int64_t(1) << 31))
      Fail(where, "more than 2^31 elements");
    const int type = t->GetField<int8_t>(kTensorType, kFloat32);
    if (type != kFloat32 && type != kFloat16 && type != kInt32)
      Fail(where, fmt::format("tensor type {} (Acrolab reads float32, float16 and int32)", type));
    tensor_types_[i] = type;
    sparse_[i] = t->GetPointer<const Table*>(kTensorSparsity);
    // The constant's bytes, if its buffer holds any (buffer 0 is the empty sentinel).
    const uint32_t buffer_index = t->GetField<uint32_t>(kTensorBuffer, 0);
    const auto* buffers = TablesField(model_, kModelBuffers);
    if (buffer_index >= buffers->size())
      Fail(where, fmt::format("buffer {} outside the {} buffers", buffer_index, buffers->size()));
    const Table* buffer = buffers->Get(buffer_index);
    if (buffer->GetField<uint64_t>(kBufferOffset, 0) > 1)
      Fail(where, "data stored outside the flatbuffer (a model over 2 GB) is not read");
    const auto* data = VectorField<uint8_t>(buffer, kBufferData);
    if (data != nullptr && data->size() > 0) {
      raw_[i].assign(data->data(), data->data() + data->size());
      tensor.constant = true;
      if (sparse_[i] == nullptr) tensor.values = DecodeDense(where, type, raw_[i], tensor.num_elements());
    }
    result_.tensors.push_back(std::move(tensor));
  }

  std::vector<float> DecodeDense(const std::string& where, int type, const std::vector<uint8_t>& raw,
                                 std::int64_t count) const {
    const std::size_t size = type == kFloat16 ? 2 : 4;
    if (static_cast<std::int64_t>(raw.size()) != count * static_cast<std::int64_t>(size))
      Fail(where, fmt::format("{} bytes of data for {} elements of {} bytes", raw.size(), count, size));
    return DecodeValues(type, raw);
  }

  static std::vector<float> DecodeValues(int type, const std::vector<uint8_t>& raw) {
    std::vector<float> values;
    if (type == kFloat16) {
      values.resize(raw.size() / 2);
      for (std::size_t k = 0; k < values.size(); ++k) {
        uint16_t h;
        std::memcpy(&h, raw.data() + 2 * k, 2);
        values[k] = HalfToFloat(h);
      }
    } else if (type == kInt32) {
      values.resize(raw.size() / 4);
      for (std::size_t k = 0; k < values.size(); ++k) {
        int32_t x;
        std::memcpy(&x, raw.data() + 4 * k, 4);
        values[k] = static_cast<float>(x);
      }
    } else {
      values.resize(raw.size() / 4);
      std::memcpy(values.data(), raw.data(), values.size() * 4);
    }
    return values;
  }

  // TFLite's sparse tensor format (schema.fbs, SparsityParameters): the stored values walked in
  // traversal order, each dimension dense (every index) or CSR (segments, indices), blocks mapped
  // back onto the dimensions they split.
  std::vector<float> Densify(int index) const {
    const TfliteTensor& tensor = result_.tensors[index];
    const std::string where = fmt::format("tensor {} ({}): sparsity", index, tensor.name);
    const Table* sparsity = sparse_[index];
    const std::vector<int> order = ReadInts(VectorField<int32_t>(sparsity, kSparseTraversal));
    const std::vector<int> block_map = ReadInts(VectorField<int32_t>(sparsity, kSparseBlockMap));
    const auto* dims = TablesField(sparsity, kSparseDims);
    const int rank = static_cast<int>(tensor.shape.size());
    const int levels = static_cast<int>(order.size());
    if (levels != rank + static_cast<int>(block_map.size()) || dims == nullptr ||
        static_cast<int>(dims->size()) != levels)
      Fail(where, "traversal order, block map and dimension metadata disagree");
    for (int k = 0; k < levels; ++k)
      if (order[k] < 0 || order[k] >= levels) Fail(where, fmt::format("traversal order {}", order[k]));
    for (int b : block_map)
      if (b < 0 || b >= rank) Fail(where, fmt::format("block map {}", b));

    struct Level {
      bool dense = true;
      int size = 0;
      std::vector<int64_t> segments, indices;
    };
    std::vector<Level> level(levels);
    for (int k = 0; k < levels; ++k) {
      const Table* d = dims->Get(k);
      level[k].dense = d->GetField<int8_t>(kDimFormat, 0) == 0;
      level[k].size = d->GetField<int32_t>(kDimDenseSize, 0);
      if (!level[k].dense) {
        level[k].segments = IndexVector(d, kDimSegmentsType, kDimSegments, where);
        level[k].indices = IndexVector(d, kDimIndicesType, kDimIndices, where);
      }
    }
    // Each stored dimension's size: a blocked dimension's outer level counts blocks.
    std::vector<int> block_size(rank, 1);
    for (std::size_t b = 0; b < block_map.size(); ++b) {
      const int block_level = rank + static_cast<int>(b);
      int position = -1;
      for (int k = 0; k < levels; ++k)
        if (order[k] == block_level) position = k;
      if (position < 0 || !level[position].dense || level[position].size <= 0)
        Fail(where, "a block dimension that is not dense");
      block_size[block_map[b]] = level[position].size;
    }

    const std::vector<float> stored = DecodeValues(tensor_types_[index], raw_[index]);
    std::vector<float> dense(static_cast<std::size_t>(tensor.num_elements()), 0.0f);
    std::vector<int64_t> strides(rank, 1);
    for (int d = rank - 2; d >= 0; --d) strides[d] = strides[d + 1] * tensor.shape[d + 1];
    std::vector<int> coordinate(levels, 0);  // per original level (traversal order → dims)

    // Depth-first walk; `position` is the linear index into the level's stored entries.
    std::function<void(int, int64_t)> walk = [&](int k, int64_t position) {
      if (k == levels) {
        if (position < 0 || position >= static_cast<int64_t>(stored.size()))
          Fail(where, "more positions than stored values");
        int64_t offset = 0;
        for (int d = 0; d < rank; ++d) {
          int64_t c = coordinate[d];
          for (std::size_t b = 0; b < block_map.size(); ++b)
            if (block_map[b] == d) c = c * block_size[d] + coordinate[rank + static_cast<int>(b)];
          if (c < 0 || c >= tensor.shape[d]) Fail(where, fmt::format("index {} outside dimension {}", c, d));
          offset += c * strides[d];
        }
        dense[static_cast<std::size_t>(offset)] = stored[static_cast<std::size_t>(position)];
        return;
      }
      const Level& l = level[k];
      if (l.dense) {
        for (int i = 0; i < l.size; ++i) {
          coordinate[order[k]] = i;
          walk(k + 1, position * l.size + i);
        }
      } else {
        if (position + 1 >= static_cast<int64_t>(l.segments.size()))
          Fail(where, "CSR segments shorter than the level above");
        const int64_t begin = l.segments[position], end = l.segments[position + 1];
        if (begin < 0 || end < begin || end > static_cast<int64_t>(l.indices.size()))
          Fail(where, fmt::format("CSR segment {}…{} outside {} indices", begin, end, l.indices.size()));
        for (int64_t j = begin; j < end; ++j) {
          coordinate[order[k]] = static_cast<int>(l.indices[j]);
          walk(k + 1, j);
        }
      }
    };
    walk(0, 0);
    return dense;
  }

  std::vector<int64_t> IndexVector(const Table* d, flatbuffers::voffset_t type_field,
                                   flatbuffers::voffset_t field, const std::string& where) const {
    const Table* vec = d->GetPointer<const Table*>(field);
    std::vector<int64_t> out;
    if (vec == nullptr) Fail(where, "a CSR dimension without its index vector");
    switch (d->GetField<uint8_t>(type_field, 0)) {
      case kInt32Vector:
        for (int32_t x : *VectorField<int32_t>(vec, Field(0))) out.push_back(x);
        break;
      case kUint16Vector:
        for (uint16_t x : *VectorField<uint16_t>(vec, Field(0))) out.push_back(x);
        break;
      case kUint8Vector:
        for (uint8_t x : *VectorField<uint8_t>(vec, Field(0))) out.push_back(x);
        break;
      default:
        Fail(where, "unknown index vector type");
    }
    return out;
  }

  void ReadOperator(int number, const Table* t) {
    const auto* codes = TablesField(model_, kModelOperatorCodes);
    const uint32_t code_index = t->GetField<uint32_t>(kOpCodeIndex, 0);
    const std::string where = fmt::format("operator {}", number);
    if (code_index >= codes->size())
      Fail(where, fmt::format("operator code {} outside the {} codes", code_index, codes->size()));
    const Table* code = codes->Get(code_index);
    // TFLite's own rule: the larger of the deprecated int8 code and the int32 one.
    const int builtin = std::max<int>(code->GetField<int8_t>(kCodeDeprecatedBuiltin, 0),
                                      code->GetField<int32_t>(kCodeBuiltin, 0));
    if (code->GetPointer<const String*>(kCodeCustom) != nullptr)
      Fail(where, fmt::format("custom operator '{}' is not read",
                              code->GetPointer<const String*>(kCodeCustom)->str()));
    TfliteOperator op;
    op.op = static_cast<TfliteOp>(builtin);
    if (std::string(TfliteOpName(op.op)) == "?")
      Fail(where, fmt::format("builtin operator {} is not one Acrolab reads", builtin));
    op.inputs = ReadInts(VectorField<int32_t>(t, kOpInputs));
    op.outputs = ReadInts(VectorField<int32_t>(t, kOpOutputs));
    for (int index : op.inputs)
      if (index != -1) CheckIndex(index, where + " (" + TfliteOpName(op.op) + ") input");
    for (int index : op.outputs) CheckIndex(index, where + " (" + TfliteOpName(op.op) + ") output");
    if (op.outputs.size() != 1) Fail(where, fmt::format("{} outputs (1 expected)", op.outputs.size()));
    ReadOptions(t, &op, where);
    CheckArity(op, where);

    // Constants behind DEQUANTIZE (float16) and DENSIFY (sparse) are folded here.
    const int in = op.inputs[0], out = op.outputs[0];
    if (op.op == TfliteOp::kDequantize || op.op == TfliteOp::kDensify) {
      TfliteTensor& source = result_.tensors[in];
      if (!source.constant)
        Fail(where, fmt::format("{} of a computed tensor is not read", TfliteOpName(op.op)));
      if (op.op == TfliteOp::kDensify && sparse_[in] == nullptr)
        Fail(where, "DENSIFY of a tensor that is not sparse");
      std::vector<float> values = sparse_[in] != nullptr ? Densify(in) : source.values;
      TfliteTensor& target = result_.tensors[out];
      if (static_cast<std::int64_t>(values.size()) != target.num_elements())
        Fail(where, fmt::format("{} values for an output of {} elements", values.size(), target.num_elements()));
      target.values = std::move(values);
      target.constant = true;
      return;
    }
    for (int index : op.inputs) {
      if (index == -1) continue;
      const TfliteTensor& input = result_.tensors[index];
      if (!input.constant && !computed_.count(index) &&
          std::find(result_.inputs.begin(), result_.inputs.end(), index) == result_.inputs.end())
        Fail(where, fmt::format("input tensor {} ({}) is used before it is computed", index, input.name));
      if (input.constant && sparse_[index] != nullptr)
        Fail(where, fmt::format("sparse tensor {} used without DENSIFY", index));
      if (input.constant && tensor_types_[index] == kFloat16)
        Fail(where, fmt::format("float16 tensor {} used without DEQUANTIZE", index));
    }
    if (result_.tensors[out].constant) Fail(where, "writes a constant tensor");
    computed_[out] = number;
    result_.operators.push_back(std::move(op));
  }

  void ReadOptions(const Table* t, TfliteOperator* op, const std::string& where) const {
    const int type = t->GetField<uint8_t>(kOpOptionsType, 0);
    const Table* o = t->GetPointer<const Table*>(kOpOptions);
    auto expect = [&](int wanted) {
      if (type != wanted || o == nullptr)
        Fail(where, fmt::format("{} without its options (union type {})", TfliteOpName(op->op), type));
    };
    auto activation = [&](int8_t a) {
      if (a != 0 && a != 1 && a != 3) Fail(where, fmt::format("fused activation {} is not read", a));
      return static_cast<TfliteActivation>(a);
    };
    switch (op->op) {
      case TfliteOp::kConv2d:
        expect(kConv2dOptions);
        op->padding_same = o->GetField<int8_t>(Field(0), 0) == 0;
        op->stride_w = o->GetField<int32_t>(Field(1), 0);
        op->stride_h = o->GetField<int32_t>(Field(2), 0);
        op->activation = activation(o->GetField<int8_t>(Field(3), 0));
        op->dilation_w = o->GetField<int32_t>(Field(4), 1);
        op->dilation_h = o->GetField<int32_t>(Field(5), 1);
        break;
      case TfliteOp::kDepthwiseConv2d:
        expect(kDepthwiseOptions);
        op->padding_same = o->GetField<int8_t>(Field(0), 0) == 0;
        op->stride_w = o->GetField<int32_t>(Field(1), 0);
        op->stride_h = o->GetField<int32_t>(Field(2), 0);
        op->depth_multiplier = o->GetField<int32_t>(Field(3), 0);
        op->activation = activation(o->GetField<int8_t>(Field(4), 0));
        op->dilation_w = o->GetField<int32_t>(Field(5), 1);
        op->dilation_h = o->GetField<int32_t>(Field(6), 1);
        break;
      case TfliteOp::kMaxPool2d:
        expect(kPool2dOptions);
        op->padding_same = o->GetField<int8_t>(Field(0), 0) == 0;
        op->stride_w = o->GetField<int32_t>(Field(1), 0);
        op->stride_h = o->GetField<int32_t>(Field(2), 0);
        op->filter_w = o->GetField<int32_t>(Field(3), 0);
        op->filter_h = o->GetField<int32_t>(Field(4), 0);
        op->activation = activation(o->GetField<int8_t>(Field(5), 0));
        break;
      case TfliteOp::kAdd:
        if (o != nullptr && type == kAddOptions) op->activation = activation(o->GetField<int8_t>(Field(0), 0));
        break;
      case TfliteOp::kConcatenation:
        expect(kConcatenationOptions);
        op->axis = o->GetField<int32_t>(Field(0), 0);
        op->activation = activation(o->GetField<int8_t>(Field(1), 0));
        break;
      case TfliteOp::kResizeBilinear:
        if (o != nullptr && type == kResizeBilinearOptions) {
          op->align_corners = o->GetField<uint8_t>(Field(2), 0) != 0;
          op->half_pixel_centers = o->GetField<uint8_t>(Field(3), 0) != 0;
        }
        break;
      case TfliteOp::kDepthToSpace:
        expect(kDepthToSpaceOptions);
        op->block_size = o->GetField<int32_t>(Field(0), 0);
        break;
      default:
        break;
    }
    const bool windowed = op->op == TfliteOp::kConv2d || op->op == TfliteOp::kDepthwiseConv2d ||
                          op->op == TfliteOp::kMaxPool2d;
    if (windowed && (op->stride_w < 1 || op->stride_h < 1 || op->stride_w > 64 || op->stride_h > 64 ||
                     op->dilation_w < 1 || op->dilation_h < 1 || op->dilation_w > 64 ||
                     op->dilation_h > 64))
      Fail(where, fmt::format("stride {}×{} or dilation {}×{} out of range", op->stride_w, op->stride_h,
                              op->dilation_w, op->dilation_h));
    if (op->op == TfliteOp::kMaxPool2d && (op->filter_w < 1 || op->filter_h < 1 || op->filter_w > 64 ||
                                           op->filter_h > 64))
      Fail(where, fmt::format("pooling window {}×{}", op->filter_w, op->filter_h));
    if (op->op == TfliteOp::kDepthToSpace && (op->block_size < 1 || op->block_size > 64))
      Fail(where, fmt::format("block size {}", op->block_size));
  }

  // The inputs each operator needs, and the shapes its arithmetic relies on.
  void CheckArity(const TfliteOperator& op, const std::string& where) const {
    std::size_t minimum = 1, maximum = 1;
    switch (op.op) {
      case TfliteOp::kAdd: minimum = maximum = 2; break;
      case TfliteOp::kConv2d:
      case TfliteOp::kDepthwiseConv2d: minimum = 2; maximum = 3; break;
      case TfliteOp::kPad:
      case TfliteOp::kResizeBilinear: minimum = maximum = 2; break;
      case TfliteOp::kReshape: minimum = 1; maximum = 2; break;
      case TfliteOp::kConcatenation: minimum = 1; maximum = 64; break;
      default: break;
    }
    if (op.inputs.size() < minimum || op.inputs.size() > maximum)
      Fail(where, fmt::format("{} with {} inputs", TfliteOpName(op.op), op.inputs.size()));
    for (std::size_t k = 0; k < op.inputs.size(); ++k)
      if (op.inputs[k] == -1 && !((op.op == TfliteOp::kConv2d || op.op == TfliteOp::kDepthwiseConv2d) && k == 2))
        Fail(where, fmt::format("{} input {} left out", TfliteOpName(op.op), k));
    const auto rank = [&](int index) { return result_.tensors[index].shape.size(); };
    if (op.op == TfliteOp::kConv2d || op.op == TfliteOp::kDepthwiseConv2d) {
      const TfliteTensor& filter = result_.tensors[op.inputs[1]];
      if (filter.shape.size() != 4 || rank(op.inputs[0]) != 4 || rank(op.outputs[0]) != 4)
        Fail(where, "a convolution whose input, filter or output is not 4-D");
      if (!filter.constant) Fail(where, "a convolution whose filter is computed");
      const int channels_out = result_.tensors[op.outputs[0]].shape[3];
      if (op.inputs.size() == 3 && op.inputs[2] != -1 &&
          result_.tensors[op.inputs[2]].num_elements() != channels_out)
        Fail(where, fmt::format("bias of {} for {} output channels",
                                result_.tensors[op.inputs[2]].num_elements(), channels_out));
    }
    if ((op.op == TfliteOp::kPad || op.op == TfliteOp::kResizeBilinear) &&
        !result_.tensors[op.inputs[1]].constant)
      Fail(where, fmt::format("{} whose second input is computed", TfliteOpName(op.op)));
  }

  const Table* model_;
  std::string source_;
  TfliteGraph result_;
  std::vector<int> tensor_types_;
  std::vector<const Table*> sparse_;
  std::vector<std::vector<uint8_t>> raw_;
  std::map<int, int> computed_;  // tensor → the operator that writes it
};

}  // namespace

const char* TfliteOpName(TfliteOp op) {
  switch (op) {
    case TfliteOp::kAdd: return "ADD";
    case TfliteOp::kConcatenation: return "CONCATENATION";
    case TfliteOp::kConv2d: return "CONV_2D";
    case TfliteOp::kDepthwiseConv2d: return "DEPTHWISE_CONV_2D";
    case TfliteOp::kDepthToSpace: return "DEPTH_TO_SPACE";
    case TfliteOp::kDequantize: return "DEQUANTIZE";
    case TfliteOp::kLogistic: return "LOGISTIC";
    case TfliteOp::kMaxPool2d: return "MAX_POOL_2D";
    case TfliteOp::kRelu: return "RELU";
    case TfliteOp::kRelu6: return "RELU6";
    case TfliteOp::kReshape: return "RESHAPE";
    case TfliteOp::kResizeBilinear: return "RESIZE_BILINEAR";
    case TfliteOp::kPad: return "PAD";
    case TfliteOp::kDensify: return "DENSIFY";
  }
  return "?";
}

std::int64_t TfliteTensor::num_elements() const {
  std::int64_t n = 1;
  for (int d : shape) n *= d;
  return n;
}

TfliteGraph ReadTfliteGraph(std::span<const std::uint8_t> bytes, const std::string& source) {
  if (bytes.size() < 8 || std::memcmp(bytes.data() + 4, "TFL3", 4) != 0)
    throw InputError(source, AtByte(4), "not a TensorFlow Lite model (no \"TFL3\" identifier)");
  if (bytes.size() >= (std::size_t(1) << 31))
    throw InputError(source, "", "larger than 2 GB");
  // The verifier reads from an aligned copy: flatbuffers checks alignment relative to the buffer's
  // start, and scalars are read in place.
  std::vector<std::uint8_t> aligned(bytes.begin(), bytes.end());
  Verifier::Options options;
  options.max_depth = 16;
  options.max_tables = 4'000'000;
  Verifier verifier(aligned.data(), aligned.size(), options);
  const flatbuffers::uoffset_t root = verifier.VerifyOffset(0);
  if (root == 0) throw InputError(source, AtByte(0), "root offset outside the file");
  const auto* model = reinterpret_cast<const Table*>(aligned.data() + root);
  if (!VerifyModel(model, verifier))
    throw InputError(source, "", "the flatbuffer fails verification (truncated or corrupt model)");
  return GraphReader(model, source).Read();
}

}  // namespace acro::pose
