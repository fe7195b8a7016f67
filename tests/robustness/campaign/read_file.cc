// The campaign's door to the readers that no acrolab command reads on its own (an OpenSim
// storage, .sto/.mot, is read by the studio's skill ghost and by overlay --ghost, which draw the
// 3D views): `acro_campaign_reader storage FILE` reads it as they do and answers as acrolab does —
// exit 0, or one line "acrolab: ..." and exit 1 for a bad file, 3 for anything else.
#include <cstdio>
#include <exception>
#include <string>

#include "acro/base/input_error.h"
#include "acro/capture/storage.h"

int main(int argc, char** argv) {
  if (argc != 3 || std::string(argv[1]) != "storage") {
    std::fprintf(stderr, "usage: acro_campaign_reader storage FILE\n");
    return 2;
  }
  try {
    const acro::capture::Storage storage = acro::capture::ReadStorage(argv[2]);
    std::printf("%zu columns\n", storage.labels.size());
    return 0;
  } catch (const acro::InputError& e) {
    std::fprintf(stderr, "acrolab: %s\n", e.what());
    return 1;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "acrolab: internal error: %s\n", e.what());
    return 3;
  }
}
