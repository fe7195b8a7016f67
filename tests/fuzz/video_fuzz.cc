// libFuzzer target for the video reader (fuzz_video.h). Built with -DACRO_BUILD_FUZZERS=ON and
// clang; scripts/fuzz.sh runs it with the samples and ../shared/refdata as seed corpus.
#include "fuzz_video.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  acro::fuzz::FeedVideoReader(data, size);
  return 0;
}
