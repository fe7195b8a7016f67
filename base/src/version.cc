#include "acro/base/version.h"

namespace acro {

const char* AcrolabVersion() {
  return ACRO_VERSION;
}

}  // namespace acro
