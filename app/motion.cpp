#include "app/motion.hpp"

#include <cmath>
#include <stdexcept>

#include "core/model.hpp"

namespace sodaevo::app {

int sample_interval(long long frames, int max_samples) {
  if (frames <= 0 || max_samples <= 1) return 1;
  const long long every = (frames + max_samples - 2) / (max_samples - 1); // samples: 0, k, 2k, ... and the last
  return static_cast<int>(std::max(1LL, std::min(every, 1000000000LL)));
}

namespace {

double tenth(double v) { return std::round(v * 10.0) / 10.0; }

bool finite_state(const soda::Model& model, const soda::State& s) {
  for (int i = 0; i < model.mass_count; ++i) {
    if (!std::isfinite(s.x[i]) || !std::isfinite(s.y[i])) return false;
  }
  return true;
}

} // namespace

Motion motion_of_model(const soda::Model& model, const std::string& name) {
  Motion m;
  m.name = name;
  m.masses = model.mass_count;
  m.width = model.width;
  m.height = model.height;
  for (int p = model.mass_count; p < model.point_count; ++p) {
    m.fixed_xy.push_back(model.x0[p]);
    m.fixed_xy.push_back(model.y0[p]);
  }
  for (int l = 0; l < model.link_count(); ++l) {
    m.links.push_back({model.link_a[l], model.link_b[l],
                       model.link_muscle[l] ? soda::LinkKind::Muscle : soda::LinkKind::Spring, model.link_rest[l]});
  }
  for (int b = 0; b < model.bar_count(); ++b) m.links.push_back({model.bar_a[b], model.bar_b[b], soda::LinkKind::FixedBar, 0.0});
  return m;
}

Motion record_motion(const soda::ModelDef& def, long long frames, int every, const soda::Stepping& stepping) {
  if (frames < 0) throw std::invalid_argument("record_motion: negative frame count");
  if (every < 1) every = 1;
  const soda::Model model = soda::build_model(def);
  Motion m = motion_of_model(model, def.name);
  m.frames = frames;
  m.every = every;

  // Without masses (a bare terrain) the camera looks at the middle of the fixed nodes.
  double fixed_centre = 0.0;
  for (std::size_t i = 0; i < m.fixed_xy.size(); i += 2) fixed_centre += m.fixed_xy[i] / static_cast<double>(m.fixed_xy.size() / 2);
  soda::State state = soda::make_state(model);
  soda::FrameStepper stepper(model, stepping, frames);
  auto keep = [&] {
    std::vector<double> xy(2 * static_cast<std::size_t>(model.mass_count));
    double sum = 0.0;
    for (int i = 0; i < model.mass_count; ++i) {
      xy[2 * i] = tenth(state.x[i]);
      xy[2 * i + 1] = tenth(state.y[i]);
      sum += state.x[i];
    }
    m.sample_frames.push_back(state.frame);
    m.mass_xy.push_back(std::move(xy));
    m.centroid_x.push_back(model.mass_count > 0 ? sum / model.mass_count : fixed_centre);
  };
  keep();
  while (state.frame < frames) {
    stepper.run(state, std::min<long long>(every, frames - state.frame));
    if (!finite_state(model, state)) {
      m.diverged = "the state became non-finite by frame " + std::to_string(state.frame);
      break;
    }
    keep();
  }
  return m;
}

Motion record_race_motion(const soda::RaceLane& lane, const soda::Model& model, int timeout, const std::string& name,
                          int max_samples) {
  Motion m = motion_of_model(model, name);
  std::vector<std::vector<double>> xy;
  std::vector<double> cx;
  const auto keep = [&](const soda::State& s) {
    std::vector<double> row;
    double sum = 0.0;
    for (int i = 0; i < model.mass_count; ++i) {
      row.push_back(tenth(s.x[static_cast<std::size_t>(i)]));
      row.push_back(tenth(s.y[static_cast<std::size_t>(i)]));
      sum += s.x[static_cast<std::size_t>(i)];
    }
    xy.push_back(std::move(row));
    cx.push_back(sum / model.mass_count);
  };
  keep(soda::make_state(model));
  const soda::RaceOutcome o = soda::run_race(lane, model, timeout, keep);
  m.frames = o.updates;
  m.every = sample_interval(o.updates, max_samples);
  for (std::size_t f = 0; f < xy.size(); ++f) {
    if (f % static_cast<std::size_t>(m.every) != 0 && f + 1 != xy.size()) continue;
    m.sample_frames.push_back(static_cast<long long>(f));
    m.mass_xy.push_back(xy[f]);
    m.centroid_x.push_back(cx[f]);
  }
  m.marks.push_back({lane.start_x, "start"});
  m.marks.push_back({lane.finish_x + 6.0, "finish"});
  return m;
}

Motion record_race_motion(const soda::RaceDef& race, int timeout, const soda::ModelDef& contender,
                          const std::string& name, int max_samples) {
  const soda::RaceLane lane = soda::build_lane(race.terrain, race.constraints, contender, name);
  return record_race_motion(lane, soda::build_lane_model(lane), timeout, name, max_samples);
}

} // namespace sodaevo::app
