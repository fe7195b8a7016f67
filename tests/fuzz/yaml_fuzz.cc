// libFuzzer target for the yaml readers (fuzz_yaml.h). Built with -DACRO_BUILD_FUZZERS=ON and
// clang; scripts/fuzz.sh runs it with the samples and ../shared/refdata as seed corpus.
#include "fuzz_yaml.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  acro::fuzz::FeedYamlReaders(data, size, ACRO_FUZZ_BASE_DIR);
  return 0;
}
