// Which sine the engine's muscles run on, by name.
//
// Walkers are chaotic: a muscle sine that differs in its last bit parts two
// trajectories within a few hundred frames, so the same config and seed evolve
// differently on engines with different sines. A run folder therefore records the
// sine that made it (manifest.json "sine", checkpoints), and replay, report and
// --resume compare it with kEngineSine (evolve/store/run_sine.hpp).
#pragma once

#include <string_view>

namespace soda {

/// The engine's sine: Java's Math.sin as HotSpot computes it on x86-64 (JDK 9
/// and later), the original SodaConstructor's sine.
inline constexpr std::string_view kEngineSine = "java-hotspot-x86_64";

/// The engine's sine before kGlibcSineUntil: the bits of glibc's x86-64 FMA sin.
/// Run folders made then record no sine; a missing record means this one.
inline constexpr std::string_view kGlibcSine = "glibc-x86_64-fma";

/// The day the engine changed from kGlibcSine to kEngineSine (for messages).
inline constexpr std::string_view kGlibcSineUntil = "2026-11-27";

} // namespace soda
