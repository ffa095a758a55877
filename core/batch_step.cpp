#include "batch_step.hpp"

#include <algorithm>
#include <array>
#include <cstdint>
#include <map>
#include <set>
#include <stdexcept>
#include <string>

#include "detail/bits.hpp"
#include "fused/fused_scene.hpp"

namespace soda {

double shared_sine_fraction(const std::vector<const Model*>& models, const std::vector<int>& members) {
  // A sine argument is 2pi * (muscle phase - wave phase): creatures whose waves
  // start alike (phase, speed, direction) and whose muscles have one phase share
  // it for as long as their waves move alike. Lockstep shares a sine between the
  // muscles of one creature too (a column), so only sharing between creatures counts.
  using Key = std::array<std::uint64_t, 4>;
  std::set<Key> between;
  std::size_t within = 0;
  for (int i : members) {
    const Model& m = *models[static_cast<std::size_t>(i)];
    std::set<Key> mine;
    for (int j = 0; j < m.link_count(); ++j) {
      if (!is_wave_muscle(m, j)) continue;
      mine.insert({bits_of(m.wave_phase0), bits_of(m.wave_speed), static_cast<std::uint64_t>(static_cast<int>(m.wave_direction0)),
                   bits_of(m.link_phase[j])});
    }
    within += mine.size();
    between.insert(mine.begin(), mine.end());
  }
  return within == 0 ? 0.0 : 1.0 - static_cast<double>(between.size()) / static_cast<double>(within);
}

BatchStepper::BatchStepper(const std::vector<const Model*>& models, long long frame_budget, FastStepOptions options,
                           const std::vector<bool>& jittered)
    : count_(static_cast<int>(models.size())), models_(models), frame_budget_(frame_budget), options_(options) {
  for (const Model* m : models) point_count_.push_back(m->point_count);
  if (!jittered.empty() && jittered.size() != models.size()) {
    throw std::invalid_argument("BatchStepper: " + std::to_string(jittered.size()) + " jitter flags for " +
                                std::to_string(models.size()) + " models");
  }
  plan(jittered.empty() ? std::vector<bool>(static_cast<std::size_t>(count_), false) : jittered);
}

void BatchStepper::plan(const std::vector<bool>& jittered) {
  const std::vector<const Model*>& models = models_;
  const FastStepOptions& options = options_;
  planned_jitter_ = jittered;
  lockstep_.reset();
  lockstep_index_.clear();
  scenes_.clear();
  alone_.clear();
  alone_index_.clear();
  // Two packs fill at once: models with fixed bars and the others. A scene with
  // bars tests every wall every frame and runs the bar pass (fused_scene.hpp), which
  // the others would pay for too.
  struct Pack {
    std::vector<const Model*> models;
    std::vector<int> index;
    int links = 0;
  };
  Pack packs[2];
  auto close_pack = [&](Pack& pack) {
    if (pack.models.empty()) return;
    scenes_.push_back({std::make_unique<FusedScene>(pack.models, frame_budget_, options), pack.index});
    pack = Pack{};
  };
  // Models of one shape, enough of them, in lockstep; which ones is decided here,
  // from the models alone and which states carry jitter.
  std::vector<bool> in_lockstep(static_cast<std::size_t>(count_), false);
  std::vector<std::vector<const Model*>> lockstep_shapes;
  const bool lockstep = options.lockstep && LockstepBatch::usable(options.simd) && !options.force_ordered && options.vector_sines;
  auto take_lockstep = [&](std::vector<int> members, bool any_sines) {
    members.resize(static_cast<std::size_t>(lockstep_share(static_cast<int>(members.size()))));
    if (members.empty() || (!any_sines && shared_sine_fraction(models, members) > kMaxSharedSines)) return;
    std::vector<const Model*> lanes;
    for (int i : members) {
      lanes.push_back(models[i]);
      in_lockstep[static_cast<std::size_t>(i)] = true;
    }
    lockstep_shapes.push_back(std::move(lanes));
    lockstep_index_.insert(lockstep_index_.end(), members.begin(), members.end());
  };
  if (lockstep) {
    std::map<const Model*, int> uses; // how many states each Model has
    for (const Model* m : models) ++uses[m];
    std::vector<std::vector<int>> shapes; // model indices by shape, in order of first appearance
    for (int i = 0; i < count_; ++i) {
      if (!LockstepBatch::can_take(*models[i])) continue;
      auto same = std::find_if(shapes.begin(), shapes.end(), [&](const std::vector<int>& members) {
        return LockstepBatch::same_shape(*models[members[0]], *models[i]);
      });
      if (same == shapes.end()) {
        shapes.push_back({i});
      } else {
        same->push_back(i);
      }
    }
    for (const std::vector<int>& members : shapes) {
      // Replicas: the states of a Model given more than once, some with jitter.
      // Their sines differ lane by lane anyway, so the shared-sine rule does not
      // apply: they go in lockstep first, whatever their sines.
      std::set<const Model*> replicated;
      for (int i : members) {
        if (jittered[static_cast<std::size_t>(i)] && uses[models[i]] > 1) {
          replicated.insert(models[i]);
        }
      }
      std::vector<int> replicas, others;
      for (int i : members) (replicated.count(models[i]) != 0 ? replicas : others).push_back(i);
      take_lockstep(replicas, true);
      for (int i : replicas) {
        if (!in_lockstep[static_cast<std::size_t>(i)]) others.push_back(i);
      }
      std::sort(others.begin(), others.end());
      take_lockstep(others, false);
    }
    if (!lockstep_shapes.empty()) lockstep_.emplace(LockstepBatch::of_shapes(lockstep_shapes, options.simd));
  }
  for (int i = 0; i < count_; ++i) {
    if (in_lockstep[static_cast<std::size_t>(i)]) continue;
    if (options.force_ordered) {
      alone_.emplace_back(*models[i], frame_budget_, options);
      alone_index_.push_back(i);
      continue;
    }
    Pack& pack = packs[models[i]->fixed_bars.empty() ? 0 : 1];
    const int links = models[i]->link_count();
    if (!pack.models.empty() && starts_new_scene(pack.links, links)) close_pack(pack);
    pack.models.push_back(models[i]);
    pack.index.push_back(i);
    pack.links += links;
  }
  close_pack(packs[0]);
  close_pack(packs[1]);
}

std::vector<std::size_t> fused_batch_ends(const std::vector<int>& links, std::size_t max_models) {
  std::vector<std::size_t> ends;
  std::size_t first = 0;
  int scene_links = 0;
  for (std::size_t i = 0; i < links.size(); ++i) {
    if (i > first && (i - first >= std::max<std::size_t>(max_models, 1) || starts_new_scene(scene_links, links[i]))) {
      ends.push_back(i);
      first = i;
      scene_links = 0;
    }
    scene_links += links[i];
  }
  if (first < links.size()) ends.push_back(links.size());
  return ends;
}

BatchStepper::~BatchStepper() = default;
BatchStepper::BatchStepper(BatchStepper&&) noexcept = default;
BatchStepper& BatchStepper::operator=(BatchStepper&&) noexcept = default;

int BatchStepper::fused_count() const {
  return count_ - static_cast<int>(alone_index_.size());
}

int BatchStepper::lockstep_count() const { return static_cast<int>(lockstep_index_.size()); }

void BatchStepper::run(const std::vector<State*>& states, long long frames) {
  if (static_cast<int>(states.size()) != count_) throw std::invalid_argument("BatchStepper::run: one state per model");
  // A State given twice is found here even where its two uses run in different
  // parts (a lockstep batch, a fused scene, alone); the parts check the sizes.
  require_batch_states(states.data(), count_, [&](int c) { return point_count_[c]; }, "BatchStepper::run");
  std::vector<bool> jittered(static_cast<std::size_t>(count_));
  for (int c = 0; c < count_; ++c) {
    require_valid_jitter_of(states[c]->jitter, "BatchStepper::run", c);
    jittered[static_cast<std::size_t>(c)] = states[c]->jitter.seed != 0;
  }
  if (jittered != planned_jitter_) plan(jittered);
  if (lockstep_) {
    scratch_.clear();
    for (int i : lockstep_index_) scratch_.push_back(states[i]);
    lockstep_->step(scratch_.data(), frames); // the states checked above
  }
  for (Scene& s : scenes_) {
    scratch_.clear();
    for (int i : s.index) scratch_.push_back(states[i]);
    s.scene->run(scratch_.data(), frames);
  }
  for (std::size_t k = 0; k < alone_.size(); ++k) alone_[k].run(*states[alone_index_[k]], frames);
}

} // namespace soda
