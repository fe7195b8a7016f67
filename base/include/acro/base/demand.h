#pragma once

#include <sstream>
#include <stdexcept>
#include <string>

/// Always-armed invariant check: throws std::logic_error naming the condition and the place.
/// For programming errors (a broken invariant), never for bad input, which gets a descriptive
/// exception from the code that read it.
#define ACRO_DEMAND(cond)                                                                   \
  do {                                                                                      \
    if (!(cond)) ::acro::internal::ThrowDemandFailure(#cond, __FILE__, __LINE__, __func__); \
  } while (0)

/// Debug-only invariant check (compiled out under NDEBUG).
#ifdef NDEBUG
#define ACRO_ASSERT(cond) \
  do {                    \
  } while (0)
#else
#define ACRO_ASSERT(cond) ACRO_DEMAND(cond)
#endif

namespace acro::internal {

[[noreturn]] inline void ThrowDemandFailure(const char* condition,
                                            const char* file,
                                            int line,
                                            const char* function) {
  std::ostringstream message;
  message << "Failure at " << file << ":" << line << " in " << function << "(): condition '"
          << condition << "' failed.";
  throw std::logic_error(message.str());
}

}  // namespace acro::internal
