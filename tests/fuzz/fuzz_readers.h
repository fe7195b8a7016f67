#pragma once

// The one entry point of the reader fuzzers: every reader of untrusted files gets the same bytes.
// A reader may accept the bytes or reject them with acro::InputError; anything else (another
// exception, a crash, a sanitizer report, a hang, an allocation beyond the fuzzer's limit) is a
// bug. Used by the libFuzzer target (tests/fuzz/readers_fuzz.cc) and by the ctest corpus replay
// (tests/capture/reader_corpus_test.cc), so the suite runs exactly what the fuzzer runs.

#include <cstddef>
#include <cstdint>
#include <span>
#include <string_view>

#include "acro/base/input_error.h"
#include "acro/capture/c3d.h"
#include "acro/capture/csv.h"
#include "acro/capture/storage.h"
#include "acro/capture/trc.h"
#include "fuzz_accepts.h"

namespace acro::fuzz {

/// Number of readers that accepted the input (0–4).
inline int FeedReaders(const std::uint8_t* data, std::size_t size) {
  const std::span<const std::uint8_t> bytes(data, size);
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  return Accepts(nullptr, [&] { capture::ReadC3dFromMemory(bytes, "fuzz.c3d"); }) +
         Accepts(nullptr, [&] { capture::ReadTrcFromString(text, "fuzz.trc"); }) +
         Accepts(nullptr, [&] { capture::ReadMarkerCsvFromString(text, "fuzz.csv"); }) +
         Accepts(nullptr, [&] { capture::ReadStorageFromString(text, "fuzz.sto"); });
}

}  // namespace acro::fuzz
