#include "fast_step.hpp"

#include <vector>

#include "fused/fused_scene.hpp"

namespace soda {

std::string KernelChoice::describe() const {
  std::string s = simd_level_name(simd);
  s += ordered ? " ordered" : " simd-masses";
  s += wave ? " wave" : " no-wave";
  s += gravity ? " gravity" : " no-gravity";
  s += " walls:";
  s += walls.floor ? "F" : "-";
  s += walls.ceiling ? "C" : "-";
  s += walls.sides ? "S" : "-";
  s += bars == BarKind::None ? " bars:none" : bars == BarKind::FixedSegments ? " bars:fixed" : " bars:moving";
  return s;
}

FastStepper::FastStepper(const Model& model, long long frame_budget, FastStepOptions options)
    : scene_(std::make_unique<FusedScene>(std::vector<const Model*>{&model}, frame_budget, options)) {}
FastStepper::~FastStepper() = default;
FastStepper::FastStepper(FastStepper&&) noexcept = default;
FastStepper& FastStepper::operator=(FastStepper&&) noexcept = default;

long long FastStepper::run_until(State& state, long long frames, const std::function<bool(double, double)>& stop) {
  return scene_->run_until(state, frames, stop);
}

const SceneNeeds& FastStepper::needs() const { return scene_->needs(0); }
const Model& FastStepper::model() const { return scene_->model(0); }
bool FastStepper::used(const KernelChoice& k) const { return scene_->used(k); }
const KernelChoice& FastStepper::last_kernel() const { return scene_->last_kernel(); }
long long FastStepper::sines_evaluated() const { return scene_->sines_evaluated(); }
long long FastStepper::bar_rules_run() const { return scene_->bar_rules_run(); }
bool FastStepper::points_in_registers() const { return scene_->points_in_registers(); }
bool FastStepper::frame_in_registers() const { return scene_->frame_in_registers(); }

void FastStepper::run(State& state, long long frames) {
  State* const st[1] = {&state};
  scene_->run(st, frames);
}

} // namespace soda
