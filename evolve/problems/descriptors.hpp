// Behaviour descriptors: what a creature's body and gait look like, as numbers,
// so that MAP-Elites (evolve/algorithms/map_elites.hpp) can keep the best walker of each kind.
//
// Each descriptor is measured on the creature as it is simulated (prepared and,
// under "sodarace" scaling, scaled) over the scored frames only: the settle frames
// are the drop, not the gait. Motion is sampled every `sample_every` scored frames
// (the last scored frame is always a sample); a sample costs one pass over the
// masses, against a pass over the links for a frame, and the steppers run whole
// chunks of frames between samples, so sampling every 8 frames costs little.
//
// The set (names as in the config's /map_elites/descriptors):
//   mass_count       number of masses (of the genome; constant)
//   muscle_share     muscles / links (constant), in [0, 1]
//   width            mean over the samples of the masses' x extent (max x - min x), px
//   height           mean over the samples of the masses' y extent, px
//   centroid_height  mean over the samples of the mass centroid's y (floor at y = 0), px
//   floor_contact    share of the samples with some mass within kFloorContact px of
//                    the floor, in [0, 1]
#pragma once

#include <array>
#include <optional>
#include <string>
#include <vector>

#include "core/model.hpp"

namespace sodaevo {

enum class Descriptor { MassCount, MuscleShare, Width, Height, CentroidHeight, FloorContact };
inline constexpr std::size_t kDescriptorCount = 6;

/// Every descriptor's value, indexed by static_cast<size_t>(Descriptor).
using Behaviour = std::array<double, kDescriptorCount>;

/// A mass this close to the floor (px) touches it. A mass resting on the floor
/// leaves it by a hair every other frame (physics_rules.hpp, friction_while_touching),
/// so an exact y == 0 test would see a resting creature touch half the time.
inline constexpr double kFloorContact = 1.0;

/// Names in the order of the enum ("mass_count", "muscle_share", ...).
const std::vector<std::string>& descriptor_names();
std::string descriptor_name(Descriptor d);
std::optional<Descriptor> descriptor_from_name(const std::string& name);

/// A behaviour as the list Evaluation::descriptors holds (enum order).
std::vector<double> behaviour_values(const Behaviour& behaviour);

/// Running sums of the descriptors over the samples of one rollout.
class DescriptorMeter {
 public:
  explicit DescriptorMeter(const soda::Model& model);
  /// One sample: the state after a scored frame.
  void observe(const soda::State& state);
  [[nodiscard]] long long samples() const { return samples_; }
  /// The descriptors (motion ones 0 before the first sample).
  [[nodiscard]] Behaviour behaviour() const;

 private:
  int masses_ = 0;
  double muscle_share_ = 0.0;
  long long samples_ = 0;
  long long touching_ = 0;
  double width_sum_ = 0.0, height_sum_ = 0.0, centroid_sum_ = 0.0;
};

} // namespace sodaevo
