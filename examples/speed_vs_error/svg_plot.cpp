// SPDX-License-Identifier: MIT
#include "svg_plot.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <sstream>

namespace speed_vs_error {
namespace {

// Colour-blind-safe palette (Okabe-Ito).
const char* const k_colours[] = {"#0072B2", "#D55E00", "#009E73", "#CC79A7", "#E69F00", "#56B4E9", "#000000"};

std::string fmt(double v) {
  char b[32];
  std::snprintf(b, sizeof b, "%.2f", v);
  return b;
}

std::string escape(const std::string& s) {
  std::string o;
  for (char c : s) {
    if (c == '<') o += "&lt;";
    else if (c == '>') o += "&gt;";
    else if (c == '&') o += "&amp;";
    else o += c;
  }
  return o;
}

std::string decade_label(int e) {
  if (e >= 0 && e <= 3) return std::to_string(static_cast<long long>(std::pow(10.0, e) + 0.5));
  return "1e" + std::to_string(e);
}

bool usable(double x, double y) { return std::isfinite(x) && std::isfinite(y) && x > 0.0 && y > 0.0; }

// [lo, hi] in whole decades around the data (at least one decade wide).
void decades(double lo, double hi, int& a, int& b) {
  a = static_cast<int>(std::floor(std::log10(lo)));
  b = static_cast<int>(std::ceil(std::log10(hi)));
  if (b <= a) b = a + 1;
}

}  // namespace

std::string svg_loglog(const std::vector<panel>& panels, const std::string& caption) {
  const double pw = 460, ph = 340, ml = 70, mr = 20, mt = 36, mb = 50, legend_h = 22;
  const double W = pw * static_cast<double>(std::max<std::size_t>(1, panels.size()));
  const double H = ph + legend_h + 26;
  std::ostringstream s;
  s << "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" << fmt(W) << "\" height=\"" << fmt(H)
    << "\" viewBox=\"0 0 " << fmt(W) << " " << fmt(H) << "\" font-family=\"sans-serif\" font-size=\"11\">\n";
  s << "<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n";
  for (std::size_t k = 0; k < panels.size(); ++k) {
    const panel& p = panels[k];
    double xlo = std::numeric_limits<double>::max(), xhi = 0.0, ylo = xlo, yhi = 0.0;
    for (const series& l : p.lines)
      for (std::size_t i = 0; i < l.x.size() && i < l.y.size(); ++i)
        if (usable(l.x[i], l.y[i])) {
          xlo = std::min(xlo, l.x[i]);
          xhi = std::max(xhi, l.x[i]);
          ylo = std::min(ylo, l.y[i]);
          yhi = std::max(yhi, l.y[i]);
        }
    if (xhi <= 0.0) xlo = 1.0, xhi = 10.0, ylo = 1.0, yhi = 10.0;
    int xa, xb, ya, yb;
    decades(xlo, xhi, xa, xb);
    decades(ylo, yhi, ya, yb);
    const double x0 = pw * static_cast<double>(k) + ml, x1 = pw * static_cast<double>(k + 1) - mr;
    const double y0 = mt, y1 = ph - mb;
    const auto px = [&](double v) { return x0 + (std::log10(v) - xa) / (xb - xa) * (x1 - x0); };
    const auto py = [&](double v) { return y1 - (std::log10(v) - ya) / (yb - ya) * (y1 - y0); };
    s << "<text x=\"" << fmt((x0 + x1) / 2) << "\" y=\"20\" text-anchor=\"middle\" font-size=\"13\">" << escape(p.title)
      << "</text>\n";
    s << "<rect x=\"" << fmt(x0) << "\" y=\"" << fmt(y0) << "\" width=\"" << fmt(x1 - x0) << "\" height=\"" << fmt(y1 - y0)
      << "\" fill=\"none\" stroke=\"black\"/>\n";
    for (int e = xa; e <= xb; ++e) {
      const double x = px(std::pow(10.0, e));
      s << "<line x1=\"" << fmt(x) << "\" y1=\"" << fmt(y0) << "\" x2=\"" << fmt(x) << "\" y2=\"" << fmt(y1)
        << "\" stroke=\"#ddd\"/>\n";
      s << "<text x=\"" << fmt(x) << "\" y=\"" << fmt(y1 + 15) << "\" text-anchor=\"middle\">" << decade_label(e)
        << "</text>\n";
    }
    for (int e = ya; e <= yb; ++e) {
      const double y = py(std::pow(10.0, e));
      s << "<line x1=\"" << fmt(x0) << "\" y1=\"" << fmt(y) << "\" x2=\"" << fmt(x1) << "\" y2=\"" << fmt(y)
        << "\" stroke=\"#ddd\"/>\n";
      s << "<text x=\"" << fmt(x0 - 5) << "\" y=\"" << fmt(y + 4) << "\" text-anchor=\"end\">" << decade_label(e)
        << "</text>\n";
    }
    s << "<text x=\"" << fmt((x0 + x1) / 2) << "\" y=\"" << fmt(y1 + 34) << "\" text-anchor=\"middle\">"
      << escape(p.x_label) << "</text>\n";
    s << "<text transform=\"translate(" << fmt(x0 - 50) << " " << fmt((y0 + y1) / 2)
      << ") rotate(-90)\" text-anchor=\"middle\">" << escape(p.y_label) << "</text>\n";
    for (std::size_t j = 0; j < p.lines.size(); ++j) {
      const series& l = p.lines[j];
      const char* c = k_colours[j % (sizeof k_colours / sizeof k_colours[0])];
      std::string pts;
      for (std::size_t i = 0; i < l.x.size() && i < l.y.size(); ++i)
        if (usable(l.x[i], l.y[i])) {
          pts += fmt(px(l.x[i])) + "," + fmt(py(l.y[i])) + " ";
          s << "<circle cx=\"" << fmt(px(l.x[i])) << "\" cy=\"" << fmt(py(l.y[i])) << "\" r=\"2.5\" fill=\"" << c
            << "\"/>\n";
        }
      s << "<polyline fill=\"none\" stroke=\"" << c << "\" stroke-width=\"1.5\" points=\"" << pts << "\"><title>"
        << escape(l.name) << "</title></polyline>\n";
    }
  }
  // Legend: the series names of the first panel (all panels share them).
  if (!panels.empty()) {
    double x = ml;
    const double y = ph + 10;
    for (std::size_t j = 0; j < panels[0].lines.size(); ++j) {
      const char* c = k_colours[j % (sizeof k_colours / sizeof k_colours[0])];
      s << "<line x1=\"" << fmt(x) << "\" y1=\"" << fmt(y) << "\" x2=\"" << fmt(x + 20) << "\" y2=\"" << fmt(y)
        << "\" stroke=\"" << c << "\" stroke-width=\"2\"/>\n";
      s << "<text x=\"" << fmt(x + 25) << "\" y=\"" << fmt(y + 4) << "\">" << escape(panels[0].lines[j].name)
        << "</text>\n";
      x += 40 + 7.0 * static_cast<double>(panels[0].lines[j].name.size());
    }
  }
  s << "<text x=\"" << fmt(ml) << "\" y=\"" << fmt(H - 8) << "\" fill=\"#555\">" << escape(caption) << "</text>\n";
  s << "</svg>\n";
  return s.str();
}

}  // namespace speed_vs_error
