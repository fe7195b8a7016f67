// acrolab-convert-model IN.tflite OUT.onnx [--bytes FIRST:END] [--outputs NAME,…]: one TFLite
// network converted to the ONNX that OpenCV's DNN reads (tools/pose_model_conversion.h).
// scripts/install-models.sh runs it for each BlazePose network; `--bytes` takes a byte range of IN
// (the person detector is the first 2 962 288 bytes of MediaPipe's packed assets); `--outputs`
// keeps only those outputs and what computes them (the landmark networks' segmentation head is
// left out: 12–15 % of their time, and Acrolab makes silhouettes its own way). The output is
// written whole or not at all.

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
  const std::string usage = "usage: acrolab-convert-model IN.tflite OUT.onnx [--bytes FIRST:END] [--outputs NAME,…]";
  if (argc < 3 || argc % 2 == 0) {
    fmt::print(stderr, "{}\n", usage);
    return 2;
  }
  try {
    const std::string in = argv[1], out = argv[2];
    std::vector<std::uint8_t> bytes = acro::ReadFileBytes(in, std::int64_t(1) << 30);
    std::size_t first = 0, end = bytes.size();
    std::vector<std::string> keep;
    for (int a = 3; a + 1 < argc; a += 2) {
      const std::string option = argv[a], value = argv[a + 1];
      if (option == "--bytes") {
        if (std::sscanf(value.c_str(), "%zu:%zu", &first, &end) != 2 || first >= end || end > bytes.size()) {
          fmt::print(stderr, "acrolab-convert-model: --bytes {}: not a range FIRST:END inside the {} bytes of {}\n",
                     value, bytes.size(), in);
          return 2;
        }
      } else if (option == "--outputs") {
        std::size_t start = 0;
        for (std::size_t comma; (comma = value.find(',', start)) != std::string::npos; start = comma + 1)
          keep.push_back(value.substr(start, comma - start));
        keep.push_back(value.substr(start));
      } else {
        fmt::print(stderr, "{}\n", usage);
        return 2;
      }
    }
    const acro::pose::TfliteGraph graph =
        acro::pose::ReadTfliteGraph(std::span(bytes).subspan(first, end - first), in);
    const std::string name = std::filesystem::path(out).stem().string();
    acro::WriteFileAtomically(out, acro::tools::ConvertTfliteToOnnx(graph, name, keep));
    fmt::print("{}: {} operators, {} tensors → {}\n", in, graph.operators.size(), graph.tensors.size(), out);
    return 0;
  } catch (const std::exception& e) {
    fmt::print(stderr, "acrolab-convert-model: {}\n", e.what());
    return 1;
  }
}
