// libFuzzer target for the camera readers (fuzz_camera.h). Built with -DACRO_BUILD_FUZZERS=ON and
// clang; scripts/fuzz.sh runs it with the samples and ../shared/refdata as seed corpus.
#include "fuzz_camera.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  acro::fuzz::FeedCameraReaders(data, size);
  return 0;
}
