#include "descriptors.hpp"

#include <algorithm>

namespace sodaevo {

const std::vector<std::string>& descriptor_names() {
  static const std::vector<std::string> names = {"mass_count", "muscle_share",    "width",
                                                 "height",     "centroid_height", "floor_contact"};
  return names;
}

std::string descriptor_name(Descriptor d) { return descriptor_names()[static_cast<std::size_t>(d)]; }

std::optional<Descriptor> descriptor_from_name(const std::string& name) {
  const auto& names = descriptor_names();
  const auto it = std::find(names.begin(), names.end(), name);
  if (it == names.end()) return std::nullopt;
  return static_cast<Descriptor>(it - names.begin());
}

std::vector<double> behaviour_values(const Behaviour& behaviour) { return {behaviour.begin(), behaviour.end()}; }

DescriptorMeter::DescriptorMeter(const soda::Model& model) : masses_(model.mass_count) {
  int muscles = 0;
  for (std::uint8_t m : model.link_muscle) muscles += m;
  if (model.link_count() > 0) muscle_share_ = static_cast<double>(muscles) / model.link_count();
}

void DescriptorMeter::observe(const soda::State& state) {
  if (masses_ == 0) return;
  double min_x = state.x[0], max_x = state.x[0], min_y = state.y[0], max_y = state.y[0];
  double sum_y = 0.0;
  for (int i = 0; i < masses_; ++i) {
    min_x = std::min(min_x, state.x[i]);
    max_x = std::max(max_x, state.x[i]);
    min_y = std::min(min_y, state.y[i]);
    max_y = std::max(max_y, state.y[i]);
    sum_y += state.y[i];
  }
  ++samples_;
  width_sum_ += max_x - min_x;
  height_sum_ += max_y - min_y;
  centroid_sum_ += sum_y / masses_;
  if (min_y <= kFloorContact) ++touching_;
}

Behaviour DescriptorMeter::behaviour() const {
  Behaviour b{};
  b[static_cast<std::size_t>(Descriptor::MassCount)] = masses_;
  b[static_cast<std::size_t>(Descriptor::MuscleShare)] = muscle_share_;
  if (samples_ > 0) {
    const double n = static_cast<double>(samples_);
    b[static_cast<std::size_t>(Descriptor::Width)] = width_sum_ / n;
    b[static_cast<std::size_t>(Descriptor::Height)] = height_sum_ / n;
    b[static_cast<std::size_t>(Descriptor::CentroidHeight)] = centroid_sum_ / n;
    b[static_cast<std::size_t>(Descriptor::FloorContact)] = static_cast<double>(touching_) / n;
  }
  return b;
}

} // namespace sodaevo
