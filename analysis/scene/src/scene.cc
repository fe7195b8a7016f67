#include "acro/scene/scene.h"

#include <cctype>

namespace acro::analysis {

BodySide SideOfName(const std::string& name) {
  std::string lower;
  for (const char c : name) lower += char(std::tolower(static_cast<unsigned char>(c)));
  const auto word = [&](const std::string& w) {
    return lower.rfind(w, 0) == 0 && (lower.size() == w.size() ||
                                      !std::isalpha(static_cast<unsigned char>(lower[w.size()])) ||
                                      std::isupper(static_cast<unsigned char>(name[w.size()])));
  };
  if (word("left")) return BodySide::kLeft;
  if (word("right")) return BodySide::kRight;
  // One letter, then a separator or a capital: l_thigh, LKnee, RASI (not Lumbar, Root, L5).
  if (name.size() >= 2 && (lower[0] == 'l' || lower[0] == 'r')) {
    const unsigned char next = static_cast<unsigned char>(name[1]);
    if (!std::isalnum(next) || std::isupper(next))
      return lower[0] == 'l' ? BodySide::kLeft : BodySide::kRight;
  }
  return BodySide::kCentre;
}

Rgba SideColour(BodySide side, Rgba centre) {
  switch (side) {
    case BodySide::kLeft:
      return {1.0f, 0.3f, 0.25f, centre.a};
    case BodySide::kRight:
      return {0.2f, 0.85f, 0.3f, centre.a};
    case BodySide::kCentre:
      break;
  }
  return centre;
}

}  // namespace acro::analysis
