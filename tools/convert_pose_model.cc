// acrolab-convert-model IN.tflite OUT.onnx [--bytes FIRST:END]: one TFLite network converted to
// the ONNX that OpenCV's DNN reads (tools/pose_model_conversion.h). scripts/install-models.sh runs
// it for each BlazePose network; `--bytes` takes a byte range of IN (the person detector is the
// first 2 962 288 bytes of MediaPipe's packed assets). The output is written whole or not at all.

#include <cstdio>
#include <exception>
#include <span>
#include <string>

#include <fmt/format.h>

#include "acro/base/file_io.h"
#include "acro/base/input_error.h"
#include "acro/pose/tflite_graph.h"
#include "pose_model_conversion.h"

int main(int argc, char** argv) {
  const std::string usage = "usage: acrolab-convert-model IN.tflite OUT.onnx [--bytes FIRST:END]";
  if (argc != 3 && argc != 5) {
    fmt::print(stderr, "{}\n", usage);
    return 2;
  }
  try {
    const std::string in = argv[1], out = argv[2];
    std::vector<std::uint8_t> bytes = acro::ReadFileBytes(in, std::int64_t(1) << 30);
    std::size_t first = 0, end = bytes.size();
    if (argc == 5) {
      if (std::string(argv[3]) != "--bytes" ||
          std::sscanf(argv[4], "%zu:%zu", &first, &end) != 2 || first >= end || end > bytes.size()) {
        fmt::print(stderr, "acrolab-convert-model: --bytes {}: not a range FIRST:END inside the {} bytes of {}\n",
                   argc == 5 ? argv[4] : "", bytes.size(), in);
        return 2;
      }
    }
    const acro::pose::TfliteGraph graph =
        acro::pose::ReadTfliteGraph(std::span(bytes).subspan(first, end - first), in);
    const std::string name = std::filesystem::path(out).stem().string();
    acro::WriteFileAtomically(out, acro::tools::ConvertTfliteToOnnx(graph, name));
    fmt::print("{}: {} operators, {} tensors → {}\n", in, graph.operators.size(), graph.tensors.size(), out);
    return 0;
  } catch (const std::exception& e) {
    fmt::print(stderr, "acrolab-convert-model: {}\n", e.what());
    return 1;
  }
}
