#include "batch_step.hpp"

#include <algorithm>
#include <stdexcept>

#include "fused_scene.hpp"

namespace soda {

BatchStepper::BatchStepper(const std::vector<const Model*>& models, long long frame_budget, FastStepOptions options)
    : count_(static_cast<int>(models.size())) {
  std::vector<const Model*> fusable;
  for (int i = 0; i < count_; ++i) {
    if (!options.force_ordered && FusedScene::can_fuse(*models[i])) {
      fusable.push_back(models[i]);
      fused_index_.push_back(i);
    } else {
      alone_.emplace_back(*models[i], frame_budget, options);
      alone_index_.push_back(i);
    }
  }
  if (!fusable.empty()) scene_ = std::make_unique<FusedScene>(fusable, frame_budget, options);
}

BatchStepper::~BatchStepper() = default;
BatchStepper::BatchStepper(BatchStepper&&) noexcept = default;
BatchStepper& BatchStepper::operator=(BatchStepper&&) noexcept = default;

bool BatchStepper::fused(int i) const {
  return std::find(fused_index_.begin(), fused_index_.end(), i) != fused_index_.end();
}

void BatchStepper::run(const std::vector<State*>& states, long long frames) {
  if (static_cast<int>(states.size()) != count_) throw std::invalid_argument("BatchStepper::run: one state per model");
  if (scene_) {
    scratch_.clear();
    for (int i : fused_index_) scratch_.push_back(states[i]);
    scene_->run(scratch_.data(), frames);
  }
  for (std::size_t k = 0; k < alone_.size(); ++k) alone_[k].run(*states[alone_index_[k]], frames);
}

} // namespace soda
