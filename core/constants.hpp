// Constants of the SodaConstructor engine and file formats.
//
// Every number the physics or the XML reader depends on is named here once, with
// its meaning and where it comes from (docs/physics.md and docs/file-formats.md
// describe the rules and formats that use them; the values were read off the
// original 2003 Soda simulator).
#pragma once

namespace soda {

// --- physics (docs/physics.md, part 2) ------------------------------------------

/// Speed limit of the "syrup" friction: above this speed (px/frame) the velocity is
/// scaled down to it. docs/physics.md part 2 step 2, constant SYRUP_THRESHOLD of the original.
inline constexpr double kSyrupThreshold = 20.0;

/// A mass whose |vx| and |vy| are both below this is not moved that frame.
/// docs/physics.md part 2 step 3, constant ZERO_VELOCITY of the original.
inline constexpr double kZeroVelocity = 1e-5;

/// 2*pi exactly as the original's double literal; part of the bit-exact muscle
/// formula (docs/physics.md, "Part 1: links").
inline constexpr double kTwoPi = 6.283185307179586;

// --- defaults of an empty model (docs/file-formats.md, v1) ----------------------

inline constexpr int kDefaultWidth = 651;
inline constexpr int kDefaultHeight = 422;
inline constexpr double kDefaultGravity = 0.3;
inline constexpr double kDefaultFriction = 0.05;
inline constexpr double kDefaultSpringyness = 0.2;
inline constexpr double kDefaultSurfaceFriction = 0.1;     // "sticky"
inline constexpr double kDefaultSurfaceReflection = -0.75; // "sticky"
inline constexpr double kDefaultWaveAmplitude = 0.5;
inline constexpr double kDefaultWavePhase = 0.0;
inline constexpr double kDefaultWaveSpeed = 0.01;

// --- ranges the original parser enforces (docs/file-formats.md, v1) ------------

struct Range {
  double min;
  double max;
  [[nodiscard]] constexpr bool contains(double v) const { return v >= min && v <= max; }
};

inline constexpr Range kGravityRange{0.0, 4.0};
inline constexpr Range kFrictionRange{0.0, 1.0};
inline constexpr Range kSpringynessRange{0.0, 0.5};
inline constexpr Range kSurfaceFrictionRange{0.0, 1.0};
inline constexpr Range kSurfaceReflectionRange{-1.0, 0.0};
/// Muscle amplitude is clamped into this range on load; the wave amplitude is
/// clamped at the top only (values above 1 become 1; negative ones are rejected).
inline constexpr Range kAmplitudeRange{0.0, 1.0};
/// Wave speed: the UI's maximum is 0.1 cycles/frame (Wave.MAX_SPEED) but the parser
/// accepts any finite value, negative included.
inline constexpr double kWaveMaxUiSpeed = 0.1;

// --- limits of this program (not of the original) ------------------------------

/// Upper bounds that keep a hostile file from exhausting memory. Far above any real
/// creature (the largest known has 136 masses).
inline constexpr long kMaxNodes = 1'000'000;
inline constexpr long kMaxLinks = 10'000'000;
/// Model files larger than this are refused before they are parsed: the largest
/// known model is a few hundred kilobytes, and the XML parser (formats/) needs
/// several times the file size in memory.
inline constexpr long kMaxModelBytes = 256L << 20;
/// Elements nested deeper than this are refused (a v1 model is 3 levels deep, a v2
/// object graph about 8); no reader recurses, but a limit keeps every later walk
/// over the tree cheap and its messages short.
inline constexpr int kMaxXmlDepth = 100;
/// Container sides are ints in the original; we require them positive.
inline constexpr long kMaxContainerSide = 2'000'000'000;

} // namespace soda
