#include "acro/analysis/line_plot.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <sstream>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

namespace acro::analysis {
namespace {

// Data range of all series, widened to avoid a zero span.
struct Range {
  double x0 = 0, x1 = 1, y0 = 0, y1 = 1;
};

Range DataRange(const LinePlot& plot) {
  Range r{std::numeric_limits<double>::max(),
          std::numeric_limits<double>::lowest(),
          std::numeric_limits<double>::max(),
          std::numeric_limits<double>::lowest()};
  for (const PlotSeries& s : plot.series) {
    for (size_t i = 0; i < s.x.size() && i < s.y.size(); ++i) {
      if (!std::isfinite(s.x[i]) || !std::isfinite(s.y[i])) continue;
      r.x0 = std::min(r.x0, s.x[i]);
      r.x1 = std::max(r.x1, s.x[i]);
      r.y0 = std::min(r.y0, s.y[i]);
      r.y1 = std::max(r.y1, s.y[i]);
    }
  }
  if (r.x0 > r.x1) r = Range{};
  if (r.x1 - r.x0 < 1e-12) r.x1 = r.x0 + 1.0;
  if (r.y1 - r.y0 < 1e-12) {
    r.y0 -= 0.5;
    r.y1 += 0.5;
  }
  const double pad = 0.05 * (r.y1 - r.y0);
  r.y0 -= pad;
  r.y1 += pad;
  return r;
}

// Plot area in pixels and the mapping from data to pixels.
struct Frame {
  double left = 80, right = 0, top = 40, bottom = 0;
  Range r;
  double X(double x) const { return left + (x - r.x0) / (r.x1 - r.x0) * (right - left); }
  double Y(double y) const { return bottom - (y - r.y0) / (r.y1 - r.y0) * (bottom - top); }
};

Frame MakeFrame(const LinePlot& plot) {
  Frame f;
  f.right = plot.width_px - 20.0;
  f.bottom = plot.height_px - 60.0;
  f.r = DataRange(plot);
  return f;
}

// About five round tick values over [a, b].
std::vector<double> Ticks(double a, double b) {
  const double raw = (b - a) / 5.0;
  const double mag = std::pow(10.0, std::floor(std::log10(raw)));
  double step = mag;
  for (double m : {1.0, 2.0, 5.0, 10.0})
    if (m * mag >= raw) {
      step = m * mag;
      break;
    }
  std::vector<double> out;
  for (double v = std::ceil(a / step) * step; v <= b + 1e-9 * step; v += step) out.push_back(v);
  return out;
}

std::string Num(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%g", std::abs(v) < 1e-12 ? 0.0 : v);
  return buf;
}

std::string Escape(const std::string& s) {
  std::string out;
  for (char c : s) {
    if (c == '<')
      out += "&lt;";
    else if (c == '>')
      out += "&gt;";
    else if (c == '&')
      out += "&amp;";
    else
      out += c;
  }
  return out;
}

std::string Hex(std::uint32_t rgb) {
  char buf[8];
  std::snprintf(buf, sizeof buf, "#%06x", rgb & 0xffffffu);
  return buf;
}

// PNG bytes of an 8-bit BGR image (OpenCV's encoder, deflate-compressed).
std::vector<std::uint8_t> EncodePng(const cv::Mat& bgr) {
  std::vector<std::uint8_t> out;
  cv::imencode(".png", bgr, out, {cv::IMWRITE_PNG_COMPRESSION, 6});
  return out;
}

cv::Scalar Bgr(std::uint32_t rgb) {
  return cv::Scalar(rgb & 0xff, (rgb >> 8) & 0xff, (rgb >> 16) & 0xff);
}

}  // namespace

std::string MakeSvgPlot(const LinePlot& plot) {
  const Frame f = MakeFrame(plot);
  std::ostringstream s;
  s << "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" << plot.width_px << "\" height=\""
    << plot.height_px << "\" font-family=\"sans-serif\" font-size=\"12\">\n";
  s << "<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n";
  s << "<text x=\"" << plot.width_px / 2 << "\" y=\"22\" text-anchor=\"middle\" font-size=\"15\">"
    << Escape(plot.title) << "</text>\n";
  // Axes, grid and tick labels.
  s << "<rect x=\"" << f.left << "\" y=\"" << f.top << "\" width=\"" << f.right - f.left
    << "\" height=\"" << f.bottom - f.top << "\" fill=\"none\" stroke=\"black\"/>\n";
  for (double v : Ticks(f.r.x0, f.r.x1)) {
    s << "<line x1=\"" << f.X(v) << "\" y1=\"" << f.top << "\" x2=\"" << f.X(v) << "\" y2=\""
      << f.bottom << "\" stroke=\"#ddd\"/>";
    s << "<text x=\"" << f.X(v) << "\" y=\"" << f.bottom + 16 << "\" text-anchor=\"middle\">"
      << Num(v) << "</text>\n";
  }
  for (double v : Ticks(f.r.y0, f.r.y1)) {
    s << "<line x1=\"" << f.left << "\" y1=\"" << f.Y(v) << "\" x2=\"" << f.right << "\" y2=\""
      << f.Y(v) << "\" stroke=\"#ddd\"/>";
    s << "<text x=\"" << f.left - 6 << "\" y=\"" << f.Y(v) + 4 << "\" text-anchor=\"end\">"
      << Num(v) << "</text>\n";
  }
  s << "<text x=\"" << (f.left + f.right) / 2 << "\" y=\"" << plot.height_px - 24
    << "\" text-anchor=\"middle\">" << Escape(plot.x_label) << "</text>\n";
  s << "<text transform=\"translate(18," << (f.top + f.bottom) / 2
    << ") rotate(-90)\" text-anchor=\"middle\">" << Escape(plot.y_label) << "</text>\n";
  // Series and legend.
  for (size_t k = 0; k < plot.series.size(); ++k) {
    const PlotSeries& ser = plot.series[k];
    s << "<polyline fill=\"none\" stroke=\"" << Hex(ser.rgb) << "\" stroke-width=\"2\""
      << (ser.dashed ? " stroke-dasharray=\"6,4\"" : "") << " points=\"";
    for (size_t i = 0; i < ser.x.size() && i < ser.y.size(); ++i)
      if (std::isfinite(ser.y[i])) s << f.X(ser.x[i]) << "," << f.Y(ser.y[i]) << " ";
    s << "\"/>\n";
    if (ser.markers)
      for (size_t i = 0; i < ser.x.size() && i < ser.y.size(); ++i)
        s << "<circle cx=\"" << f.X(ser.x[i]) << "\" cy=\"" << f.Y(ser.y[i])
          << "\" r=\"3.5\" fill=\"" << Hex(ser.rgb) << "\"/>";
    const double ly = f.top + 16 + 18.0 * static_cast<double>(k);
    s << "\n<line x1=\"" << f.left + 10 << "\" y1=\"" << ly - 4 << "\" x2=\"" << f.left + 34
      << "\" y2=\"" << ly - 4 << "\" stroke=\"" << Hex(ser.rgb)
      << "\" stroke-width=\"2\"/><text x=\"" << f.left + 40 << "\" y=\"" << ly << "\">"
      << Escape(ser.name) << "</text>\n";
  }
  s << "</svg>\n";
  return s.str();
}

std::vector<std::uint8_t> RenderPngPlot(const LinePlot& plot) {
  const Frame f = MakeFrame(plot);
  cv::Mat img(plot.height_px, plot.width_px, CV_8UC3, cv::Scalar(255, 255, 255));
  const int font = cv::FONT_HERSHEY_SIMPLEX;
  auto pt = [](double x, double y) {
    return cv::Point(static_cast<int>(std::lround(x)), static_cast<int>(std::lround(y)));
  };
  auto text = [&](const std::string& t, double x, double y, double scale, double anchor) {
    int base = 0;
    const cv::Size size = cv::getTextSize(t, font, scale, 1, &base);
    cv::putText(
        img, t, pt(x - anchor * size.width, y), font, scale, cv::Scalar(0, 0, 0), 1, cv::LINE_AA);
  };
  // Grid, frame, ticks.
  for (double v : Ticks(f.r.x0, f.r.x1)) {
    cv::line(img, pt(f.X(v), f.top), pt(f.X(v), f.bottom), cv::Scalar(221, 221, 221), 1);
    text(Num(v), f.X(v), f.bottom + 18, 0.4, 0.5);
  }
  for (double v : Ticks(f.r.y0, f.r.y1)) {
    cv::line(img, pt(f.left, f.Y(v)), pt(f.right, f.Y(v)), cv::Scalar(221, 221, 221), 1);
    text(Num(v), f.left - 6, f.Y(v) + 4, 0.4, 1.0);
  }
  cv::rectangle(img, pt(f.left, f.top), pt(f.right, f.bottom), cv::Scalar(0, 0, 0), 1);
  // Hershey fonts are ASCII: the PNG's labels drop other characters (the SVG keeps them).
  auto ascii = [](const std::string& s) {
    std::string out;
    for (unsigned char c : s)
      if (c < 128) out += static_cast<char>(c);
    return out;
  };
  text(ascii(plot.title), plot.width_px / 2.0, 24, 0.55, 0.5);
  text(ascii(plot.x_label), (f.left + f.right) / 2, plot.height_px - 22.0, 0.45, 0.5);
  text(ascii(plot.y_label), 6, f.top - 10, 0.45, 0.0);
  for (size_t k = 0; k < plot.series.size(); ++k) {
    const PlotSeries& ser = plot.series[k];
    std::vector<cv::Point> pts;
    for (size_t i = 0; i < ser.x.size() && i < ser.y.size(); ++i)
      if (std::isfinite(ser.y[i])) pts.push_back(pt(f.X(ser.x[i]), f.Y(ser.y[i])));
    if (ser.dashed) {
      for (size_t i = 0; i + 1 < pts.size(); i += 2)
        cv::line(img, pts[i], pts[i + 1], Bgr(ser.rgb), 2, cv::LINE_AA);
    } else if (!pts.empty()) {
      cv::polylines(img, pts, false, Bgr(ser.rgb), 2, cv::LINE_AA);
    }
    if (ser.markers)
      for (const cv::Point& p : pts) cv::circle(img, p, 4, Bgr(ser.rgb), cv::FILLED, cv::LINE_AA);
    const double ly = f.top + 16 + 18.0 * static_cast<double>(k);
    cv::line(img, pt(f.left + 10, ly - 4), pt(f.left + 34, ly - 4), Bgr(ser.rgb), 2);
    text(ascii(ser.name), f.left + 40, ly, 0.42, 0.0);
  }
  return EncodePng(img);
}

}  // namespace acro::analysis
