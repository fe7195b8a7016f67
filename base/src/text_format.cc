#include "acro/base/text_format.h"

#include <fmt/format.h>

namespace acro {

std::string FormatFixed(double v, int digits) {
  return fmt::format("{:.{}f}", v, digits);
}

}  // namespace acro
