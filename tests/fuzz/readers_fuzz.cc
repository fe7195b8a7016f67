// libFuzzer target for every file reader (C3D, TRC, CSV, OpenSim storage). Built with
// -DACRO_BUILD_FUZZERS=ON and clang; scripts/fuzz.sh runs it with ../shared/refdata as seed corpus.
#include "fuzz_readers.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  acro::fuzz::FeedReaders(data, size);
  return 0;
}
