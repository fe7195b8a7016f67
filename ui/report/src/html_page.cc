#include "html_page.h"

#include <fmt/format.h>

#include "acro/base/text_format.h"

namespace acro::ui::internal {

std::string HtmlPageStart(std::string_view title, int max_width_px) {
  return fmt::format(
      "<!DOCTYPE html>\n<html><head><meta charset=\"utf-8\"><title>{}</title><style>"
      "body{{font-family:sans-serif;max-width:{}px;margin:2em auto;color:#222}}"
      "table{{border-collapse:collapse;margin:0.5em 0}}"
      "td,th{{border:1px solid #ccc;padding:2px 6px;text-align:right}}td.l,th.l{{text-align:left}}"
      ".pass{{color:#1a7f37}}.fail{{color:#c62828}}.warning{{color:#a40}}"
      ".note{{background:#fff8e1;padding:0.5em}}img{{max-width:100%}}"
      "</style></head><body>\n",
      HtmlEscape(std::string(title)), max_width_px);
}

}  // namespace acro::ui::internal
