#include "app/filmstrip_svg.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>
#include <vector>

#include "app/creature_style.hpp"
#include "charts/svg_chart.hpp"
#include "core/number_text.hpp"

namespace sodaevo::app {

using charts::svg_escape;

namespace {

std::string num(double v) { return soda::format_printf("%.1f", v); }
std::string signed_px(double v) { return soda::format_printf("%+.0f px", v); }

} // namespace

std::string render_filmstrip_svg(const Motion& motion, const FilmstripOptions& options) {
  const int n_samples = static_cast<int>(motion.samples());
  const int stills = std::max(1, std::min(options.stills, std::max(n_samples, 1)));
  std::vector<int> chosen;
  for (int i = 0; i < stills && n_samples > 0; ++i) {
    chosen.push_back(stills == 1 ? 0 : static_cast<int>(std::lround(static_cast<double>(i) * (n_samples - 1) / (stills - 1))));
  }

  // One scale for every panel: the creature's widest reach from its centroid and
  // its greatest height over the chosen frames.
  double half_width = 10.0, top = 10.0;
  for (int s : chosen) {
    const std::vector<double>& xy = motion.mass_xy[static_cast<std::size_t>(s)];
    for (std::size_t i = 0; i + 1 < xy.size(); i += 2) {
      half_width = std::max(half_width, std::fabs(xy[i] - motion.centroid_x[static_cast<std::size_t>(s)]));
      top = std::max(top, xy[i + 1]);
    }
  }
  if (motion.masses == 0 && !motion.centroid_x.empty()) { // a bare scene: fit its fixed nodes
    for (std::size_t i = 0; i + 1 < motion.fixed_xy.size(); i += 2) {
      half_width = std::max(half_width, std::fabs(motion.fixed_xy[i] - motion.centroid_x.front()));
      top = std::max(top, motion.fixed_xy[i + 1]);
    }
  }
  const double pw = std::max(80, options.panel_width);
  const double scale = std::min((pw - 24.0) / (2.0 * half_width), 170.0 / top);
  const double floor_y = 34.0 + top * scale + 12.0; // panel-local pixel y of the floor
  const double ph = floor_y + 40.0;
  const double gap = 8.0, margin = 10.0;
  const double width = margin * 2 + stills * pw + (stills - 1) * gap;
  const double height = 40.0 + ph + margin;
  const double x0 = motion.centroid_x.empty() ? 0.0 : motion.centroid_x.front();
  const double tick = style::nice_step(pw / scale, 3.0);

  std::ostringstream o;
  const std::string title = options.title.empty() ? (motion.name.empty() ? std::string("creature") : motion.name) : options.title;
  o << "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n"
    << "<svg xmlns=\"http://www.w3.org/2000/svg\" version=\"1.1\" class=\"filmstrip\" width=\"" << num(width)
    << "\" height=\"" << num(height) << "\" viewBox=\"0 0 " << num(width) << ' ' << num(height)
    << "\" font-family=\"Helvetica, Arial, sans-serif\" font-size=\"11\">\n"
    << "<rect x=\"0\" y=\"0\" width=\"" << num(width) << "\" height=\"" << num(height) << "\" fill=\"white\"/>\n";
  const long long last_frame = motion.sample_frames.empty() ? 0 : motion.sample_frames.back();
  o << "<text class=\"title\" x=\"" << num(margin) << "\" y=\"24\" font-size=\"14\" font-weight=\"bold\">"
    << svg_escape(title) << "</text>\n"
    << "<text class=\"summary\" x=\"" << num(width - margin) << "\" y=\"24\" text-anchor=\"end\">"
    << svg_escape("centroid moved " + signed_px(motion.distance()) + " in " + std::to_string(last_frame) + " frames" +
                  (motion.diverged.empty() ? "" : " (" + motion.diverged + ")"))
    << "</text>\n";
  o << "<defs>\n";
  for (int k = 0; k < stills; ++k) {
    o << "<clipPath id=\"still-clip-" << k << "\"><rect x=\"0\" y=\"0\" width=\"" << num(pw) << "\" height=\""
      << num(ph) << "\" rx=\"6\"/></clipPath>\n";
  }
  o << "</defs>\n";

  for (int k = 0; k < stills; ++k) {
    const std::size_t s = static_cast<std::size_t>(chosen[static_cast<std::size_t>(k)]);
    const std::vector<double>& xy = motion.mass_xy[s];
    const double cx = motion.centroid_x[s];
    auto sx = [&](double x) { return pw / 2 + (x - cx) * scale; };
    auto sy = [&](double y) { return floor_y - y * scale; };
    auto point = [&](int p, double& x, double& y) {
      if (p < motion.masses) {
        x = xy[2 * static_cast<std::size_t>(p)];
        y = xy[2 * static_cast<std::size_t>(p) + 1];
      } else {
        x = motion.fixed_xy[2 * static_cast<std::size_t>(p - motion.masses)];
        y = motion.fixed_xy[2 * static_cast<std::size_t>(p - motion.masses) + 1];
      }
    };
    const double px = margin + k * (pw + gap);
    o << "<g class=\"still\" data-frame=\"" << motion.sample_frames[s] << "\" transform=\"translate(" << num(px) << " 40)\">\n"
      << "<g clip-path=\"url(#still-clip-" << k << ")\">\n"
      << "<rect x=\"0\" y=\"0\" width=\"" << num(pw) << "\" height=\"" << num(ph) << "\" fill=\"" << style::kBackground << "\"/>\n"
      << "<rect class=\"ground\" x=\"0\" y=\"" << num(floor_y) << "\" width=\"" << num(pw) << "\" height=\"" << num(ph - floor_y)
      << "\" fill=\"" << style::kGround << "\"/>\n"
      << "<line class=\"floor\" x1=\"0\" y1=\"" << num(floor_y) << "\" x2=\"" << num(pw) << "\" y2=\"" << num(floor_y)
      << "\" stroke=\"" << style::kFloor << "\" stroke-width=\"2\"/>\n";
    // Distance marks: px from where the centroid started.
    const double left = cx - pw / 2 / scale, right = cx + pw / 2 / scale;
    for (double d = std::ceil((left - x0) / tick) * tick; x0 + d <= right; d += tick) {
      const double tx = sx(x0 + d);
      o << "<line class=\"mark\" x1=\"" << num(tx) << "\" y1=\"" << num(floor_y) << "\" x2=\"" << num(tx) << "\" y2=\""
        << num(floor_y + (d == 0 ? 12 : 6)) << "\" stroke=\"" << style::kTick << "\"/>\n"
        << "<text class=\"mark\" x=\"" << num(tx) << "\" y=\"" << num(floor_y + 20) << "\" text-anchor=\"middle\" font-size=\"9\" fill=\""
        << style::kTick << "\">" << (d == 0 ? std::string("start") : soda::format_double_plain(std::round(d))) << "</text>\n";
    }
    // Container walls and ceiling where they are in view.
    for (double wx : {0.0, motion.width}) {
      if (wx >= left && wx <= right) {
        o << "<line class=\"wall\" x1=\"" << num(sx(wx)) << "\" y1=\"0\" x2=\"" << num(sx(wx)) << "\" y2=\"" << num(floor_y)
          << "\" stroke=\"" << style::kFloor << "\" stroke-width=\"3\"/>\n";
      }
    }
    for (const MotionLink& l : motion.links) {
      double ax, ay, bx, by;
      point(l.a, ax, ay);
      point(l.b, bx, by);
      std::string color = style::kSpring;
      double w = style::kSpringWidth;
      const char* cls = "spring";
      if (l.kind == soda::LinkKind::Muscle) {
        const double stretch = style::muscle_stretch(std::hypot(bx - ax, by - ay), l.rest);
        color = style::muscle_color(stretch);
        w = style::muscle_width(stretch);
        cls = "muscle";
      } else if (l.kind == soda::LinkKind::FixedBar) {
        color = style::kBar;
        w = style::kBarWidth;
        cls = "bar";
      }
      o << "<line class=\"" << cls << "\" x1=\"" << num(sx(ax)) << "\" y1=\"" << num(sy(ay)) << "\" x2=\"" << num(sx(bx))
        << "\" y2=\"" << num(sy(by)) << "\" stroke=\"" << color << "\" stroke-width=\"" << num(w)
        << "\" stroke-linecap=\"round\"/>\n";
    }
    for (std::size_t f = 0; f + 1 < motion.fixed_xy.size(); f += 2) {
      const double side = style::kFixedSide;
      o << "<rect class=\"fixed\" x=\"" << num(sx(motion.fixed_xy[f]) - side / 2) << "\" y=\"" << num(sy(motion.fixed_xy[f + 1]) - side / 2)
        << "\" width=\"" << num(side) << "\" height=\"" << num(side) << "\" fill=\"" << style::kFixed << "\"/>\n";
    }
    for (std::size_t i = 0; i + 1 < xy.size(); i += 2) {
      o << "<circle class=\"mass\" cx=\"" << num(sx(xy[i])) << "\" cy=\"" << num(sy(xy[i + 1])) << "\" r=\""
        << num(style::kMassRadius) << "\" fill=\"" << style::kMass << "\"/>\n";
    }
    o << "</g>\n"
      << "<rect x=\"0\" y=\"0\" width=\"" << num(pw) << "\" height=\"" << num(ph) << "\" rx=\"6\" fill=\"none\" stroke=\"#cfc8bb\"/>\n"
      << "<text class=\"caption\" x=\"8\" y=\"16\">frame " << motion.sample_frames[s] << "</text>\n"
      << "<text class=\"caption\" x=\"" << num(pw - 8) << "\" y=\"16\" text-anchor=\"end\">"
      << svg_escape(signed_px(cx - x0)) << "</text>\n"
      << "</g>\n";
  }
  o << "</svg>\n";
  return o.str();
}

} // namespace sodaevo::app
