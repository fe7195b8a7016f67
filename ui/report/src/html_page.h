#pragma once

// The page every HTML report of ui/report shares (analyze's report, optimize's, the routine's, the
// season's progress): the doctype, UTF-8, the title, one stylesheet — tables with right-aligned
// numbers (`l` cells left), the verdict's colours (`pass`, `fail`), notes, warnings, pictures no
// wider than the page — and the end.

#include <string>
#include <string_view>

namespace acro::ui::internal {

/// Everything up to and including <body>: `title` (escaped here) in the window's title bar, the
/// page `max_width_px` wide.
std::string HtmlPageStart(std::string_view title, int max_width_px);

/// What closes the page.
inline constexpr std::string_view kHtmlPageEnd = "</body></html>\n";

}  // namespace acro::ui::internal
