// How creatures are drawn, in one place for the SVG filmstrip and the canvas player
// (the player gets these values from the page, see player_html.cpp): masses round,
// fixed nodes square, springs thin grey, fixed bars thick black, muscles red and
// thicker the more they are contracted, pale and thin when stretched.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

namespace sodaevo::app::style {

inline constexpr const char* kBackground = "#fbfaf7";
inline constexpr const char* kFloor = "#6b5a45";
inline constexpr const char* kGround = "#e9e2d6";
inline constexpr const char* kTick = "#8a7a66";
inline constexpr const char* kSpring = "#8c8c8c";
inline constexpr const char* kBar = "#222222";
inline constexpr const char* kMass = "#1f4e8c";
inline constexpr const char* kFixed = "#111111";
inline constexpr double kMassRadius = 4.0;   ///< screen px
inline constexpr double kFixedSide = 8.0;    ///< screen px
inline constexpr double kSpringWidth = 1.5;
inline constexpr double kBarWidth = 4.0;
/// Muscle colour and width run from contracted (length/rest <= 1 - kMuscleRange)
/// to stretched (>= 1 + kMuscleRange).
inline constexpr double kMuscleRange = 0.25;
inline constexpr int kMuscleContracted[3] = {150, 15, 25};
inline constexpr int kMuscleRest[3] = {220, 50, 40};
inline constexpr int kMuscleStretched[3] = {245, 165, 120};
inline constexpr double kMuscleWidthContracted = 5.0;
inline constexpr double kMuscleWidthStretched = 2.0;

/// -1 fully contracted .. 0 at rest .. +1 fully stretched.
inline double muscle_stretch(double length, double rest) {
  if (!(rest > 0)) return 0.0;
  return std::clamp((length / rest - 1.0) / kMuscleRange, -1.0, 1.0);
}

inline std::string muscle_color(double stretch) {
  const int* to = stretch < 0 ? kMuscleContracted : kMuscleStretched;
  const double t = std::fabs(stretch);
  char buf[16];
  std::snprintf(buf, sizeof buf, "#%02x%02x%02x", static_cast<int>(std::lround(kMuscleRest[0] + (to[0] - kMuscleRest[0]) * t)),
                static_cast<int>(std::lround(kMuscleRest[1] + (to[1] - kMuscleRest[1]) * t)),
                static_cast<int>(std::lround(kMuscleRest[2] + (to[2] - kMuscleRest[2]) * t)));
  return buf;
}

inline double muscle_width(double stretch) {
  const double mid = (kMuscleWidthContracted + kMuscleWidthStretched) / 2;
  return mid + (kMuscleWidthStretched - kMuscleWidthContracted) / 2 * stretch;
}

/// A round step (1, 2 or 5 times a power of ten) near span / count.
inline double nice_step(double span, double count) {
  const double raw = std::max(span / std::max(count, 1.0), 1e-9);
  const double mag = std::pow(10.0, std::floor(std::log10(raw)));
  for (double m : {1.0, 2.0, 5.0}) {
    if (m * mag >= raw) return m * mag;
  }
  return 10.0 * mag;
}

} // namespace sodaevo::app::style
