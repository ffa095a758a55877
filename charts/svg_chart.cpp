#include "charts/svg_chart.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <iterator>
#include <sstream>

#include "core/number_text.hpp"

namespace sodaevo::charts {

namespace {

constexpr const char* kPalette[] = {"#1f77b4", "#d62728", "#2ca02c", "#ff7f0e", "#9467bd",
                                    "#8c564b", "#e377c2", "#7f7f7f", "#bcbd22", "#17becf"};
constexpr int kPaletteSize = sizeof kPalette / sizeof kPalette[0];

std::string num(double v) { return soda::format_printf("%.2f", v); }

/// Maps data values to pixels along one axis.
struct Scale {
  bool log = false;
  bool integer = false;      // ticks at whole numbers only
  double lo = 0, hi = 1;     // data range (log10 of it for log axes)
  double p_lo = 0, p_hi = 1; // pixel range
  [[nodiscard]] double operator()(double v) const {
    const double t = log ? std::log10(v) : v;
    return p_lo + (t - lo) / (hi - lo) * (p_hi - p_lo);
  }
  [[nodiscard]] bool usable(double v) const { return std::isfinite(v) && (!log || v > 0); }
};

/// Data range of `values` for the axis, with fixed ends honoured.
void fit_range(const ChartAxis& axis, const std::vector<double>& values, bool include_zero, double& lo, double& hi) {
  lo = std::numeric_limits<double>::infinity();
  hi = -lo;
  for (double v : values) {
    if (!std::isfinite(v) || (axis.log && v <= 0)) continue;
    lo = std::min(lo, v);
    hi = std::max(hi, v);
  }
  if (!(lo <= hi)) lo = hi = axis.log ? 1.0 : 0.0;
  if (axis.log) {
    lo = std::floor(std::log10(lo));
    hi = std::ceil(std::log10(hi));
    if (hi <= lo) hi = lo + 1;
  } else {
    if (include_zero) lo = std::min(lo, 0.0), hi = std::max(hi, 0.0);
    if (hi <= lo) hi = lo + 1;
    const double pad = (hi - lo) * 0.05;
    if (!(include_zero && lo == 0.0)) lo -= pad;
    hi += pad;
  }
  if (std::isfinite(axis.min)) lo = axis.log ? std::log10(axis.min) : axis.min;
  if (std::isfinite(axis.max)) hi = axis.log ? std::log10(axis.max) : axis.max;
  if (hi <= lo) hi = lo + 1;
}

/// Tick values (in data units) for a scale.
std::vector<double> ticks_for(const Scale& s) {
  std::vector<double> ticks;
  if (s.log) {
    const int a = static_cast<int>(std::ceil(s.lo - 1e-9)), b = static_cast<int>(std::floor(s.hi + 1e-9));
    const bool dense = b - a <= 2;
    for (int e = a - 1; e <= b; ++e) {
      for (double m : dense ? std::vector<double>{1, 2, 5} : std::vector<double>{1}) {
        const double v = m * std::pow(10.0, e);
        const double t = std::log10(v);
        if (t >= s.lo - 1e-9 && t <= s.hi + 1e-9) ticks.push_back(v);
      }
    }
    return ticks;
  }
  return round_ticks(s.lo, s.hi, s.integer);
}

struct Frame {
  int width, height;
  double left = 84, right = 180, top = 48, bottom = 64;
  [[nodiscard]] double x0() const { return left; }
  [[nodiscard]] double x1() const { return width - right; }
  [[nodiscard]] double y0() const { return height - bottom; } // pixel y of the bottom
  [[nodiscard]] double y1() const { return top; }
};

/// The frame for a chart whose legend lists `names` to the right of the plot: the
/// picture grows wider, rather than the plot narrower, when a name would not fit
/// the default right margin (a long name is cut off at the picture's edge otherwise).
Frame frame_with_legend(int width, int height, const std::vector<std::string>& names) {
  Frame f{width, height};
  double widest = 0.0;
  for (const std::string& name : names) widest = std::max(widest, text_width_estimate(name, 12.0));
  const double needed = 16 + 24 + widest + 8; // legend gap, swatch, name, margin
  if (needed > f.right) {
    const int extra = static_cast<int>(std::ceil(needed - f.right));
    f.width += extra;
    f.right += extra;
  }
  return f;
}

void open_svg(std::ostringstream& o, const Frame& f, const std::string& title) {
  o << "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n"
    << "<svg xmlns=\"http://www.w3.org/2000/svg\" version=\"1.1\" width=\"" << f.width << "\" height=\""
    << f.height << "\" viewBox=\"0 0 " << f.width << ' ' << f.height
    << "\" font-family=\"Helvetica, Arial, sans-serif\" font-size=\"12\">\n"
    << "<rect x=\"0\" y=\"0\" width=\"" << f.width << "\" height=\"" << f.height << "\" fill=\"white\"/>\n"
    << "<text class=\"title\" x=\"" << num(f.width / 2.0) << "\" y=\"24\" text-anchor=\"middle\" font-size=\"15\" "
    << "font-weight=\"bold\">" << svg_escape(title) << "</text>\n";
}

void y_axis(std::ostringstream& o, const Frame& f, const Scale& sy, const std::string& label) {
  o << "<g class=\"y-axis\">\n";
  for (double v : ticks_for(sy)) {
    const double py = sy(v);
    o << "<line x1=\"" << num(f.x0()) << "\" y1=\"" << num(py) << "\" x2=\"" << num(f.x1()) << "\" y2=\"" << num(py)
      << "\" stroke=\"#e5e5e5\"/>\n";
    o << "<line x1=\"" << num(f.x0() - 5) << "\" y1=\"" << num(py) << "\" x2=\"" << num(f.x0()) << "\" y2=\""
      << num(py) << "\" stroke=\"black\"/>\n";
    o << "<text class=\"tick\" x=\"" << num(f.x0() - 8) << "\" y=\"" << num(py + 4) << "\" text-anchor=\"end\">"
      << svg_escape(format_tick(v)) << "</text>\n";
  }
  o << "<line x1=\"" << num(f.x0()) << "\" y1=\"" << num(f.y0()) << "\" x2=\"" << num(f.x0()) << "\" y2=\""
    << num(f.y1()) << "\" stroke=\"black\"/>\n";
  const double cy = (f.y0() + f.y1()) / 2;
  o << "<text class=\"axis-label\" x=\"18\" y=\"" << num(cy) << "\" text-anchor=\"middle\" transform=\"rotate(-90 18 "
    << num(cy) << ")\">" << svg_escape(label) << "</text>\n";
  o << "</g>\n";
}

void legend(std::ostringstream& o, const Frame& f, const std::vector<std::string>& names, bool bars) {
  o << "<g class=\"legend\">\n";
  double y = f.y1() + 6;
  const double x = f.x1() + 16;
  for (std::size_t i = 0; i < names.size(); ++i, y += 20) {
    const char* color = kPalette[i % kPaletteSize];
    if (bars) {
      o << "<rect x=\"" << num(x) << "\" y=\"" << num(y - 5) << "\" width=\"18\" height=\"10\" fill=\"" << color
        << "\"/>\n";
    } else {
      o << "<line x1=\"" << num(x) << "\" y1=\"" << num(y) << "\" x2=\"" << num(x + 18) << "\" y2=\"" << num(y)
        << "\" stroke=\"" << color << "\" stroke-width=\"2\"/>\n";
    }
    o << "<text x=\"" << num(x + 24) << "\" y=\"" << num(y + 4) << "\">" << svg_escape(names[i]) << "</text>\n";
  }
  o << "</g>\n";
}

} // namespace

std::string svg_escape(const std::string& text) {
  std::string out;
  out.reserve(text.size());
  for (char c : text) {
    switch (c) {
      case '&': out += "&amp;"; break;
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      case '"': out += "&quot;"; break;
      case '\'': out += "&apos;"; break;
      default: out += c;
    }
  }
  return out;
}

std::vector<double> round_ticks(double lo, double hi, bool integer) {
  std::vector<double> ticks;
  const double span = hi - lo;
  if (!(span > 0) || !std::isfinite(span)) return ticks;
  const double raw = span / 6.0;
  const double mag = std::pow(10.0, std::floor(std::log10(raw)));
  double step = mag;
  for (double m : {1.0, 2.0, 5.0, 10.0}) {
    if (m * mag >= raw) {
      step = m * mag;
      break;
    }
  }
  if (integer) step = std::max(1.0, std::round(step));
  for (double v = std::ceil(lo / step) * step; v <= hi + step * 1e-9; v += step) {
    ticks.push_back(std::fabs(v) < step * 1e-9 ? 0.0 : v);
  }
  return ticks;
}

double text_width_estimate(const std::string& text, double font_size) {
  // Advance widths in em, rounded up from DejaVu Sans (Arial and Helvetica are
  // narrower); unlisted characters count as wide as a capital.
  double em = 0.0;
  for (const char ch : text) {
    const unsigned char c = static_cast<unsigned char>(ch);
    if ((c & 0xC0) == 0x80) continue; // a UTF-8 continuation byte: counted with its lead byte
    if (c == ' ' || c == '.' || c == ',' || c == ':' || c == ';' || c == '\'' || c == '!' || c == '|' || c == 'i' ||
        c == 'j' || c == 'l') {
      em += 0.34;
    } else if (c == '(' || c == ')' || c == '[' || c == ']' || c == '-' || c == 'f' || c == 't' || c == 'r' ||
               c == '/') {
      em += 0.42;
    } else if (c == 'm' || c == 'w' || c == 'M' || c == 'W' || c == '%' || c == '@' || c >= 0x80) {
      em += 1.0;
    } else if ((c >= 'a' && c <= 'z') || (c >= '0' && c <= '9')) {
      em += 0.64;
    } else {
      em += 0.85; // capitals, < > + = and the rest
    }
  }
  return em * font_size;
}

std::string format_tick(double v) {
  if (v == 0) return "0";
  char buf[32];
  if (std::fabs(v) < 1e-3) {
    std::snprintf(buf, sizeof buf, "%.0e", v);
    return buf;
  }
  struct Unit {
    double scale;
    const char* suffix;
  };
  static constexpr Unit kUnits[] = {{1.0, ""}, {1e3, "k"}, {1e6, "M"}, {1e9, "G"}, {1e12, "T"}};
  // The largest unit not above |v|; the next one up where three significant
  // digits round to 1000 (999.96M is 1G, not 1e+03M).
  std::size_t u = 0;
  while (u + 1 < std::size(kUnits) && std::fabs(v) >= kUnits[u + 1].scale) ++u;
  std::snprintf(buf, sizeof buf, "%.3g", v / kUnits[u].scale);
  if (std::fabs(std::strtod(buf, nullptr)) >= 1000 && u + 1 < std::size(kUnits)) {
    ++u;
    std::snprintf(buf, sizeof buf, "%.3g", v / kUnits[u].scale);
  }
  return std::string(buf) + kUnits[u].suffix;
}

std::string render_line_chart(const LineChart& chart) {
  std::vector<std::string> legend_names;
  for (const LineSeries& s : chart.series) legend_names.push_back(s.name);
  const Frame f = frame_with_legend(chart.width, chart.height, legend_names);
  std::vector<double> xs, ys;
  for (const LineSeries& s : chart.series) {
    xs.insert(xs.end(), s.x.begin(), s.x.end());
    ys.insert(ys.end(), s.y.begin(), s.y.end());
  }
  Scale sx{chart.x_axis.log, chart.x_axis.integer}, sy{chart.y_axis.log, chart.y_axis.integer};
  fit_range(chart.x_axis, xs, false, sx.lo, sx.hi);
  fit_range(chart.y_axis, ys, false, sy.lo, sy.hi);
  sx.p_lo = f.x0(), sx.p_hi = f.x1();
  sy.p_lo = f.y0(), sy.p_hi = f.y1();

  std::ostringstream o;
  open_svg(o, f, chart.title);
  y_axis(o, f, sy, chart.y_axis.label);
  o << "<g class=\"x-axis\">\n";
  for (double v : ticks_for(sx)) {
    const double px = sx(v);
    o << "<line x1=\"" << num(px) << "\" y1=\"" << num(f.y0()) << "\" x2=\"" << num(px) << "\" y2=\"" << num(f.y1())
      << "\" stroke=\"#f0f0f0\"/>\n";
    o << "<line x1=\"" << num(px) << "\" y1=\"" << num(f.y0()) << "\" x2=\"" << num(px) << "\" y2=\""
      << num(f.y0() + 5) << "\" stroke=\"black\"/>\n";
    o << "<text class=\"tick\" x=\"" << num(px) << "\" y=\"" << num(f.y0() + 18) << "\" text-anchor=\"middle\">"
      << svg_escape(format_tick(v)) << "</text>\n";
  }
  o << "<line x1=\"" << num(f.x0()) << "\" y1=\"" << num(f.y0()) << "\" x2=\"" << num(f.x1()) << "\" y2=\""
    << num(f.y0()) << "\" stroke=\"black\"/>\n";
  o << "<text class=\"axis-label\" x=\"" << num((f.x0() + f.x1()) / 2) << "\" y=\"" << num(f.height - 18.0)
    << "\" text-anchor=\"middle\">" << svg_escape(chart.x_axis.label) << "</text>\n";
  o << "</g>\n";

  std::vector<std::string> names;
  for (std::size_t i = 0; i < chart.series.size(); ++i) {
    const LineSeries& s = chart.series[i];
    names.push_back(s.name);
    const char* color = kPalette[i % kPaletteSize];
    std::string points;
    std::ostringstream markers;
    for (std::size_t k = 0; k < std::min(s.x.size(), s.y.size()); ++k) {
      if (!sx.usable(s.x[k]) || !sy.usable(s.y[k])) continue;
      const double px = sx(s.x[k]), py = sy(s.y[k]);
      points += num(px) + "," + num(py) + " ";
      if (s.markers) {
        markers << "<circle cx=\"" << num(px) << "\" cy=\"" << num(py) << "\" r=\"3\" fill=\"" << color << "\"/>\n";
      }
    }
    if (!points.empty()) points.pop_back();
    o << "<g class=\"series\" data-name=\"" << svg_escape(s.name) << "\">\n";
    o << "<polyline fill=\"none\" stroke=\"" << color << "\" stroke-width=\"2\""
      << (s.dashed ? " stroke-dasharray=\"6 4\"" : "") << " points=\"" << points << "\"/>\n";
    o << markers.str() << "</g>\n";
  }
  legend(o, f, names, false);
  o << "</svg>\n";
  return o.str();
}

std::string render_bar_chart(const BarChart& chart) {
  std::vector<std::string> legend_names;
  for (const BarSeries& s : chart.series) legend_names.push_back(s.name);
  const Frame f = frame_with_legend(chart.width, chart.height, legend_names);
  std::vector<double> ys;
  for (const BarSeries& s : chart.series) ys.insert(ys.end(), s.values.begin(), s.values.end());
  Scale sy{chart.y_axis.log, chart.y_axis.integer};
  fit_range(chart.y_axis, ys, true, sy.lo, sy.hi);
  sy.p_lo = f.y0(), sy.p_hi = f.y1();

  std::ostringstream o;
  open_svg(o, f, chart.title);
  y_axis(o, f, sy, chart.y_axis.label);
  const std::size_t groups = std::max<std::size_t>(chart.categories.size(), 1);
  const double group_w = (f.x1() - f.x0()) / static_cast<double>(groups);
  const std::size_t n = std::max<std::size_t>(chart.series.size(), 1);
  const double bar_w = group_w * 0.8 / static_cast<double>(n);
  const double base = sy.log ? f.y0() : sy(std::clamp(0.0, sy.lo, sy.hi));
  o << "<g class=\"x-axis\">\n";
  for (std::size_t g = 0; g < chart.categories.size(); ++g) {
    o << "<text class=\"tick\" x=\"" << num(f.x0() + group_w * (g + 0.5)) << "\" y=\"" << num(f.y0() + 18)
      << "\" text-anchor=\"middle\">" << svg_escape(chart.categories[g]) << "</text>\n";
  }
  o << "<line x1=\"" << num(f.x0()) << "\" y1=\"" << num(f.y0()) << "\" x2=\"" << num(f.x1()) << "\" y2=\""
    << num(f.y0()) << "\" stroke=\"black\"/>\n";
  o << "</g>\n";
  std::vector<std::string> names;
  for (std::size_t i = 0; i < chart.series.size(); ++i) {
    const BarSeries& s = chart.series[i];
    names.push_back(s.name);
    o << "<g class=\"series\" data-name=\"" << svg_escape(s.name) << "\">\n";
    for (std::size_t g = 0; g < std::min(s.values.size(), chart.categories.size()); ++g) {
      const double v = s.values[g];
      if (!sy.usable(v)) continue;
      const double top = std::clamp(sy(v), f.y1(), f.y0());
      const double x = f.x0() + group_w * (g + 0.1) + bar_w * i;
      o << "<rect x=\"" << num(x) << "\" y=\"" << num(std::min(top, base)) << "\" width=\"" << num(bar_w * 0.92)
        << "\" height=\"" << num(std::fabs(base - top)) << "\" fill=\"" << kPalette[i % kPaletteSize] << "\"/>\n";
      if (chart.value_labels) {
        o << "<text class=\"value\" x=\"" << num(x + bar_w * 0.46) << "\" y=\"" << num(std::min(top, base) - 3)
          << "\" text-anchor=\"middle\" font-size=\"9\">" << svg_escape(format_tick(v)) << "</text>\n";
      }
    }
    o << "</g>\n";
  }
  legend(o, f, names, true);
  o << "</svg>\n";
  return o.str();
}

} // namespace sodaevo::charts
