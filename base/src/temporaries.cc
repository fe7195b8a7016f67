#include "acro/base/temporaries.h"

#include <mutex>
#include <set>
#include <system_error>

namespace acro {

namespace {

std::mutex& RegistryMutex() {
  static std::mutex m;
  return m;
}

std::multiset<std::filesystem::path>& Registry() {
  static std::multiset<std::filesystem::path> paths;
  return paths;
}

}  // namespace

ScopedTemporary::ScopedTemporary(std::filesystem::path path) : path_(std::move(path)) {
  const std::lock_guard<std::mutex> lock(RegistryMutex());
  Registry().insert(path_);
}

ScopedTemporary::~ScopedTemporary() {
  const std::lock_guard<std::mutex> lock(RegistryMutex());
  const auto it = Registry().find(path_);
  if (it != Registry().end()) Registry().erase(it);
}

int RemoveRegisteredTemporaries() noexcept {
  int removed = 0;
  try {
    const std::lock_guard<std::mutex> lock(RegistryMutex());
    for (const std::filesystem::path& p : Registry()) {
      std::error_code ec;
      if (std::filesystem::remove_all(p, ec) > 0 && !ec) ++removed;
    }
    Registry().clear();
  } catch (...) {
    // Nothing to report to: the program is stopping.
  }
  return removed;
}

}  // namespace acro
