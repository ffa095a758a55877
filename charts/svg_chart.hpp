// A small SVG chart writer: line charts (optionally log-log) and grouped bar charts,
// with axes, ticks, tick labels, axis labels, a legend and a title. Self-contained
// SVG 1.1 text (no scripts, no external fonts or styles), so the files render the
// same in browsers and on GitHub. Used by the benchmarks (bench/) and the run
// reports (app/).
#pragma once

#include <limits>
#include <string>
#include <vector>

namespace sodaevo::charts {

struct ChartAxis {
  std::string label;
  bool log = false; ///< log10 scale (values <= 0 are left out)
  /// Fixed range; NaN = from the data (with a little margin).
  double min = std::numeric_limits<double>::quiet_NaN();
  double max = std::numeric_limits<double>::quiet_NaN();
  bool integer = false; ///< linear axes: ticks only at whole numbers (generations, counts)
};

struct LineSeries {
  std::string name;
  std::vector<double> x, y; ///< same length; non-finite points are left out
  bool markers = true;
  bool dashed = false;
};

struct LineChart {
  std::string title;
  ChartAxis x_axis, y_axis;
  std::vector<LineSeries> series;
  int width = 760;
  int height = 460;
};

struct BarSeries {
  std::string name;
  std::vector<double> values; ///< one per category
};

struct BarChart {
  std::string title;
  std::vector<std::string> categories; ///< groups along x
  ChartAxis y_axis;                    ///< x_axis is categorical
  std::vector<BarSeries> series;       ///< one bar per series in each group
  int width = 760;
  int height = 460;
  bool value_labels = true; ///< print each bar's value above it
};

std::string render_line_chart(const LineChart& chart);
std::string render_bar_chart(const BarChart& chart);

/// Text for an SVG text node or attribute: & < > " ' escaped.
std::string svg_escape(const std::string& text);

/// Compact number label: 1.5k, 20M, 0.25, 1e-06.
std::string format_tick(double value);

/// Round tick values in [lo, hi] for a linear axis: every multiple there of a step
/// of 1, 2 or 5 times a power of ten, the smallest such step giving at most about
/// six intervals (`integer`: a step of at least 1).
std::vector<double> round_ticks(double lo, double hi, bool integer = false);

/// The width in px of `text` set in a sans-serif font of `font_size` px, estimated
/// from DejaVu Sans's advance widths (Debian's sans-serif) and erring wide, so a
/// layout that leaves this much room does not cut a label off.
double text_width_estimate(const std::string& text, double font_size);

} // namespace sodaevo::charts
