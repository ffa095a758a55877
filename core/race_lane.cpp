#include "race_lane.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "batch_step.hpp"
#include "contender_filter.hpp"
#include "fast_step.hpp"
#include "fused/fused_scene.hpp"
#include "input_error.hpp"
#include "lockstep_batch.hpp"
#include "step.hpp"

namespace soda {

int java_int(double v) {
  if (std::isnan(v)) return 0;
  if (v >= 2147483647.0) return std::numeric_limits<int>::max();
  if (v <= -2147483648.0) return std::numeric_limits<int>::min();
  return static_cast<int>(v);
}

namespace {

template <typename T>
T pick(RaceSource source, const T& contender, const T& racer) {
  return source == RaceSource::Racer ? racer : contender;
}

} // namespace

RaceLane build_lane(const ModelDef& terrain, const RaceConstraints& rc, const ModelDef& contender,
                    const std::string& contender_name) {
  RaceLane lane;
  ModelDef& d = lane.def;
  // Terrain (FilterFixedBars): fixed nodes in order, bars between them.
  std::vector<int> index(terrain.nodes.size(), -1);
  for (std::size_t i = 0; i < terrain.nodes.size(); ++i) {
    if (!terrain.nodes[i].fixed) continue;
    index[i] = static_cast<int>(d.nodes.size());
    d.nodes.push_back(terrain.nodes[i]);
  }
  if (d.nodes.empty()) throw InputError("race terrain: expected fixed nodes, got none");
  std::size_t start = 0, finish = 0;
  for (std::size_t i = 1; i < d.nodes.size(); ++i) {
    if (d.nodes[i].x < d.nodes[start].x) start = i;
    if (d.nodes[i].x > d.nodes[finish].x) finish = i;
  }
  const double dx = kRacePlatformWidth - d.nodes[start].x;
  for (NodeDef& n : d.nodes) n.x = n.x + dx;
  lane.start_x = d.nodes[start].x;
  lane.start_y = d.nodes[start].y;
  lane.finish_x = d.nodes[finish].x;
  lane.finish_y = d.nodes[finish].y;
  const int left_platform = static_cast<int>(d.nodes.size());
  d.nodes.push_back({"", true, 0.0, lane.start_y, 0.0, 0.0});
  d.nodes.push_back({"", true, lane.finish_x + kRacePlatformWidth, lane.finish_y, 0.0, 0.0});
  std::vector<LinkDef> bars;
  for (const LinkDef& l : terrain.links) {
    if (l.kind != LinkKind::FixedBar) continue;
    const int a = index[static_cast<std::size_t>(l.a)], b = index[static_cast<std::size_t>(l.b)];
    if (a < 0 || b < 0) continue;
    bars.push_back({LinkKind::FixedBar, a, b, 0.0, 0.0, 0.0});
  }
  bars.push_back({LinkKind::FixedBar, left_platform, static_cast<int>(start), 0.0, 0.0, 0.0});
  bars.push_back({LinkKind::FixedBar, static_cast<int>(finish), left_platform + 1, 0.0, 0.0, 0.0});

  // Contender (FilterScaledSquare: contender_filter.hpp), placed 6 px left of the
  // start and 7 px above it, by the kept masses only.
  const FilteredContender sc = filter_contender(contender, contender_name);
  lane.scale = sc.scale;
  lane.contender_masses = sc.pieces.masses;
  lane.contender_pieces = sc.pieces.pieces;
  double min_y = sc.masses[0].y, max_x = sc.masses[0].x;
  for (const NodeDef& m : sc.masses) {
    min_y = std::min(min_y, m.y);
    max_x = std::max(max_x, m.x);
  }
  const double px = (lane.start_x - 6.0) - static_cast<double>(java_int(max_x));
  const double py = (lane.start_y + 7.0) - static_cast<double>(java_int(min_y));
  const int first_mass = static_cast<int>(d.nodes.size());
  for (NodeDef m : sc.masses) {
    m.x = m.x + px;
    m.y = m.y + py;
    d.nodes.push_back(m);
  }
  // Links as the racer's lane lists them: terrain bars, the two platforms, then the
  // contender's kept links (its mass-to-mass bars among them). Bars are tested in
  // link order, so the contender's bars come after the terrain's.
  d.links = std::move(bars);
  for (LinkDef l : sc.links) {
    l.a += first_mass;
    l.b += first_mass;
    d.links.push_back(l);
  }
  for (std::size_t i = 0; i < d.nodes.size(); ++i) {
    d.nodes[i].id = (d.nodes[i].fixed ? "n" : "m") + std::to_string(i);
  }

  // Header: the contender's values or the terrain's, as the constraints say.
  d.name = contender.name;
  d.width = java_int(lane.finish_x + kRacePlatformWidth);
  d.height = terrain.height;
  const ModelDef& c = contender;
  const ModelDef& t = terrain;
  d.environment.gravity = pick(rc.gravity, c.environment.gravity * sc.scale, t.environment.gravity);
  d.environment.friction = pick(rc.friction, c.environment.friction, t.environment.friction);
  d.environment.springyness = pick(rc.springyness, c.environment.springyness, t.environment.springyness);
  d.collisions.surface_friction =
      pick(rc.surface_friction, c.collisions.surface_friction, t.collisions.surface_friction);
  d.collisions.surface_reflection =
      pick(rc.surface_reflection, c.collisions.surface_reflection, t.collisions.surface_reflection);
  d.wave.amplitude = pick(rc.wave_amplitude, c.wave.amplitude, t.wave.amplitude);
  d.wave.phase = pick(rc.wave_phase, c.wave.phase, t.wave.phase);
  d.wave.speed = pick(rc.wave_speed, c.wave.speed, t.wave.speed);
  d.settings.gravity_direction =
      pick(rc.gravity_direction, c.settings.gravity_direction, t.settings.gravity_direction);
  d.settings.autoreverse = pick(rc.autoreverse, c.settings.autoreverse, t.settings.autoreverse);
  const bool racer_wave = rc.wave_direction == RaceSource::Racer && rc.wave_speed == RaceSource::Racer;
  d.settings.wave_direction = racer_wave ? t.settings.wave_direction : c.settings.wave_direction;
  return lane;
}

Model build_lane_model(const RaceLane& lane) {
  ModelDef def = lane.def;
  // A link from a mass to itself has length 0, and the engine skips such a link;
  // build_model refuses one.
  std::erase_if(def.links, [](const LinkDef& l) { return l.a == l.b && l.kind != LinkKind::FixedBar; });
  // The racer multiplies the contender's gravity by its scale and checks no range:
  // gravity may exceed the editor's limit of 4 (a contender scaled up), and a scale
  // of +inf makes gravity, positions, velocities and rest lengths infinite or NaN.
  // build_model refuses those, so it gets stand-ins and the lane's values go in after.
  const double gravity = def.environment.gravity;
  const bool gravity_out = !kGravityRange.contains(gravity);
  if (gravity_out) def.environment.gravity = kGravityRange.max;
  const auto finite_or_zero = [](double& v) {
    if (std::isfinite(v)) return false;
    v = 0.0;
    return true;
  };
  bool nodes_out = false, links_out = false;
  for (NodeDef& n : def.nodes) {
    for (double* v : {&n.x, &n.y, &n.vx, &n.vy}) nodes_out = finite_or_zero(*v) || nodes_out;
  }
  for (LinkDef& l : def.links) links_out = finite_or_zero(l.rest_length) || links_out;
  Model model = build_model(def, BarEngine::Racer2004);
  if (nodes_out) {
    for (int p = 0; p < model.point_count; ++p) {
      const NodeDef& n = lane.def.nodes[static_cast<std::size_t>(model.node_of_point[static_cast<std::size_t>(p)])];
      const auto k = static_cast<std::size_t>(p);
      model.x0[k] = n.x;
      model.y0[k] = n.y;
      model.vx0[k] = model.is_mass(p) ? n.vx : 0.0;
      model.vy0[k] = model.is_mass(p) ? n.vy : 0.0;
    }
    model.fixed_bars = make_fixed_bars(model.bar_a, model.bar_b, model.x0.data(), model.y0.data(), BarEngine::Racer2004);
  }
  if (links_out) { // the model's links are def's springs and muscles, in order
    std::size_t k = 0;
    for (const LinkDef& l : lane.def.links) {
      if (l.kind == LinkKind::FixedBar || l.a == l.b) continue;
      model.link_rest[k++] = l.rest_length;
    }
  }
  if (gravity_out) {
    model.gravity = gravity;
    set_constants(model);
  }
  return model;
}

bool passed_finish(const RaceLane& lane, double min_x) {
  return static_cast<double>(java_int(min_x)) > lane.finish_x + 6.0;
}

bool race_ends(const RaceLane& lane, int timeout, long long updates, double min_x, double max_x,
               RaceOutcome& out) {
  const int left = java_int(min_x);
  const int right = java_int(max_x);
  out.updates = updates;
  if (passed_finish(lane, min_x)) {
    out.result = static_cast<double>(updates - 2);
    out.finished = true;
    return true;
  }
  if (updates - 2 > timeout) {
    const double fraction = (lane.finish_x + 6.0 - left) / (lane.finish_x - lane.start_x + 12.0 + (right - left));
    out.result = static_cast<double>(static_cast<float>(timeout + fraction));
    out.finished = false;
    return true;
  }
  return false;
}

double least_x(const Model& model, const State& state) {
  double min_x = state.x[0];
  for (int i = 1; i < model.mass_count; ++i) min_x = std::min(min_x, state.x[static_cast<std::size_t>(i)]);
  return min_x;
}

namespace {

constexpr long long kRacerUpdateLimit = 50000; // the racer throws after this many updates

/// Keeps the most of a least x (NaN never counts: a diverged racer held no ground).
void hold_furthest(double& furthest, double min_x) {
  if (min_x > furthest) furthest = min_x;
}

/// Whether the race ends after update `u` of `state`; out.furthest_min_x also holds
/// this state's least x.
bool ends_after(const RaceLane& lane, const Model& model, int timeout, long long u, const State& state,
                RaceOutcome& out) {
  double min_x = state.x[0], max_x = state.x[0];
  for (int i = 1; i < model.mass_count; ++i) {
    min_x = std::min(min_x, state.x[static_cast<std::size_t>(i)]);
    max_x = std::max(max_x, state.x[static_cast<std::size_t>(i)]);
  }
  hold_furthest(out.furthest_min_x, min_x);
  return race_ends(lane, timeout, u, min_x, max_x, out);
}

/// The update that ends a race of `timeout` at the latest (the timeout's, or the racer's limit).
long long last_update(int timeout) { return std::min<long long>(kRacerUpdateLimit, static_cast<long long>(timeout) + 3); }

/// Whether races of `model` can run in lockstep lanes: the CPU has them, the model
/// fits them, and the timeout ends every race by update timeout + 3 (else the
/// racer's limit may come first: then one by one, run_race_fast throwing for the
/// state it reaches).
bool races_in_lockstep(const Model& model, int timeout) {
  return LockstepBatch::usable() && LockstepBatch::can_take(model) &&
         static_cast<long long>(timeout) + 3 <= kRacerUpdateLimit;
}

[[noreturn]] void racer_limit() {
  throw InputError("race: still in progress after 50000 updates (the racer's limit)");
}

} // namespace

RaceOutcome run_race(const RaceLane& lane, const Model& model, int timeout,
                     const std::function<void(const State&)>& on_frame) {
  State state = make_state(model);
  RaceOutcome out;
  out.furthest_min_x = least_x(model, state);
  for (long long u = 1; u <= kRacerUpdateLimit; ++u) {
    step(model, state);
    if (on_frame) on_frame(state);
    if (ends_after(lane, model, timeout, u, state, out)) return out;
  }
  racer_limit();
}

RaceOutcome run_race_fast(const RaceLane& lane, const Model& model, int timeout, State& state, long long every,
                          const std::function<void(const State&)>& observe) {
  RaceOutcome out;
  // The timeout ends the race at update timeout + 3; the finish is watched after
  // every frame inside the stepper (same extremes as ends_after takes). A state
  // partway through its race goes on from its update state.frame.
  const long long left = std::max(0LL, last_update(timeout) - state.frame);
  FastStepper stepper(model, left);
  double furthest = least_x(model, state);
  const auto finished = [&](double min_x, double) {
    hold_furthest(furthest, min_x);
    return passed_finish(lane, min_x);
  };
  if (every <= 0 || !observe) {
    stepper.run_until(state, left, finished);
    out.furthest_min_x = furthest;
    if (ends_after(lane, model, timeout, state.frame, state, out)) return out;
    racer_limit();
  }
  for (long long done = 0;;) { // in chunks, observed after each
    done += stepper.run_until(state, std::min(every, left - done), finished);
    observe(state);
    out.furthest_min_x = furthest;
    if (ends_after(lane, model, timeout, state.frame, state, out)) return out;
    if (done >= left) racer_limit();
  }
}

std::vector<RaceOutcome> run_races_fast(const RaceLane& lane, const Model& model, int timeout,
                                        const std::vector<State*>& states) {
  const long long last = last_update(timeout);
  std::vector<RaceOutcome> out(states.size());
  const int share = lockstep_share(static_cast<int>(states.size()));
  const bool lockstep = share > 0 && races_in_lockstep(model, timeout);
  std::size_t first_alone = 0;
  if (lockstep) {
    LockstepBatch batch(std::vector<const Model*>(static_cast<std::size_t>(share), &model));
    std::vector<long long> done;
    std::vector<double> furthest;
    for (int c = 0; c < share; ++c) furthest.push_back(least_x(model, *states[static_cast<std::size_t>(c)]));
    batch.run_until(
        states.data(), last,
        [&](int c, double min_x, double) {
          hold_furthest(furthest[static_cast<std::size_t>(c)], min_x);
          return passed_finish(lane, min_x);
        },
        done);
    for (int c = 0; c < share; ++c) {
      const std::size_t k = static_cast<std::size_t>(c);
      out[k].furthest_min_x = furthest[k];
      if (!ends_after(lane, model, timeout, done[k], *states[k], out[k])) racer_limit();
    }
    first_alone = static_cast<std::size_t>(share);
  }
  for (std::size_t c = first_alone; c < states.size(); ++c) out[c] = run_race_fast(lane, model, timeout, *states[c]);
  return out;
}

namespace {

/// run_races_together for races[group], the ones that can go on (update limit and
/// state allow) in fused scenes while two or more run; sets their outcomes and
/// marks them decided.
void race_group_fused(const std::vector<LaneRace>& races, const std::vector<std::size_t>& group,
                      std::vector<RaceOutcome>& out, std::vector<bool>& decided) {
  // out[r].furthest_min_x holds race r's furthest least x so far (set by the caller).
  std::vector<std::size_t> active;
  for (std::size_t r : group) {
    const LaneRace& race = races[r];
    if (static_cast<long long>(race.timeout) + 3 <= kRacerUpdateLimit && race.state->frame < last_update(race.timeout)) {
      active.push_back(r);
    }
  }
  while (active.size() >= 2) {
    std::vector<const Model*> models;
    std::vector<State*> states;
    std::vector<long long> start, calls(active.size(), 0);
    long long longest = 0;
    for (std::size_t r : active) {
      models.push_back(races[r].model);
      states.push_back(races[r].state);
      start.push_back(races[r].state->frame);
      longest = std::max(longest, last_update(races[r].timeout) - races[r].state->frame);
    }
    FusedScene scene(models, longest);
    // stop(c) is called once per frame while c runs: calls[c] counts its frames here.
    const auto stop = [&](int c, double min_x, double) {
      const std::size_t k = static_cast<std::size_t>(c);
      const LaneRace& race = races[active[k]];
      hold_furthest(out[active[k]].furthest_min_x, min_x);
      return start[k] + ++calls[k] >= last_update(race.timeout) || passed_finish(*race.lane, min_x);
    };
    std::vector<long long> done;
    std::vector<bool> stopped;
    // Fewer than three quarters still running: a smaller scene for them (the
    // stopped ones' masses are still stepped in this one, without their bar rules).
    // Measured on the 41 golden contenders' TerrainFlat races: at half, the stepping
    // of stopped creatures made the races together 0.90x of one by one; at three
    // quarters 0.99x (bench races, "Fused lanes").
    scene.run_until(states.data(), longest, stop, done, stopped, static_cast<int>((3 * active.size() + 3) / 4));
    std::vector<std::size_t> still;
    for (std::size_t k = 0; k < active.size(); ++k) {
      const LaneRace& race = races[active[k]];
      if (!stopped[k]) {
        still.push_back(active[k]);
        continue;
      }
      if (!ends_after(*race.lane, *race.model, race.timeout, race.state->frame, *race.state, out[active[k]])) {
        racer_limit();
      }
      decided[active[k]] = true;
    }
    active = std::move(still);
  }
}

} // namespace

std::vector<RaceOutcome> run_races_together(const std::vector<LaneRace>& races) {
  std::vector<RaceOutcome> out(races.size());
  std::vector<bool> decided(races.size(), false);
  // Replicas: fresh states of one lane model (the same lane, model and timeout), in
  // lockstep lanes by whole groups (run_races_fast), as BatchStepper takes them.
  std::vector<std::vector<std::size_t>> replicas;
  for (std::size_t r = 0; r < races.size(); ++r) {
    if (races[r].state->frame != 0) continue;
    auto same = std::find_if(replicas.begin(), replicas.end(), [&](const std::vector<std::size_t>& g) {
      const LaneRace& a = races[g[0]];
      return a.lane == races[r].lane && a.model == races[r].model && a.timeout == races[r].timeout;
    });
    if (same == replicas.end()) {
      replicas.push_back({r});
    } else {
      same->push_back(r);
    }
  }
  for (std::vector<std::size_t>& group : replicas) {
    const LaneRace& first = races[group[0]];
    group.resize(static_cast<std::size_t>(lockstep_share(static_cast<int>(group.size()))));
    if (group.empty() || !races_in_lockstep(*first.model, first.timeout)) continue;
    std::vector<State*> states;
    for (std::size_t r : group) states.push_back(races[r].state);
    const std::vector<RaceOutcome> raced = run_races_fast(*first.lane, *first.model, first.timeout, states);
    for (std::size_t k = 0; k < group.size(); ++k) {
      out[group[k]] = raced[k];
      decided[group[k]] = true;
    }
  }
  // The others in fused scenes of at most kMaxFusedLinks links, as BatchStepper packs them.
  std::vector<std::size_t> rest;
  std::vector<int> links;
  for (std::size_t r = 0; r < races.size(); ++r) {
    if (decided[r]) continue;
    out[r].furthest_min_x = least_x(*races[r].model, *races[r].state);
    rest.push_back(r);
    links.push_back(races[r].model->link_count());
  }
  std::size_t first = 0;
  for (std::size_t end : fused_batch_ends(links, rest.size())) {
    race_group_fused(races, std::vector<std::size_t>(rest.begin() + static_cast<std::ptrdiff_t>(first),
                                                     rest.begin() + static_cast<std::ptrdiff_t>(end)),
                     out, decided);
    first = end;
  }
  for (std::size_t r = 0; r < races.size(); ++r) { // the last of a group, or past the racer's limit
    if (decided[r]) continue;
    const double before = out[r].furthest_min_x; // from a fused scene it left partway, if any
    out[r] = run_race_fast(*races[r].lane, *races[r].model, races[r].timeout, *races[r].state);
    hold_furthest(out[r].furthest_min_x, before);
  }
  return out;
}

} // namespace soda
