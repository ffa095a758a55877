#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "app/commands.hpp"
#include "app/stepping_options.hpp"
#include "core/divergence.hpp"
#include "core/fast_step.hpp"
#include "core/input_error.hpp"
#include "core/model.hpp"
#include "core/number_text.hpp"
#include "core/stability.hpp"
#include "core/step.hpp"
#include "core/simulation_run.hpp"
#include "core/stepping.hpp"
#include "evolve/problems/honesty.hpp"
#include "evolve/estimators/replica_ensemble.hpp"
#include "evolve/estimators/sample_summary.hpp"
#include "formats/model_file.hpp"
#include "formats/trace_csv.hpp"

namespace sodaevo::app {

namespace {

struct SimulateOptions {
  std::string model;
  long long frames = 1000;
  bool json = false;
  std::string trace;
  std::string out;
  bool reference = false;
  SteppingOptions stepping;
  bool energy_check = false;
  bool honesty = false;
  int honesty_factor = 4;
  // --replicas (simulate_replicas)
  int replicas = 0; ///< 0: one plain run
  double jitter = 0.002;
  long long settle = 0;
  std::string bar_engine = "2003";
  bool stability = false;
  long long stability_every = 10;
};

struct SimulateSummary {
  long long frames = 0;
  int masses = 0;
  int links = 0;
  double centroid_dx = 0.0;
  double centroid_dy = 0.0;
  double wall_seconds = 0.0;
  std::string stepping = "soda";
  std::string bar_engine = "2003";
  int bars = 0;
  soda::Divergence divergence;
  bool honesty = false;
  std::string honesty_stepping;
  double honesty_centroid_dx = 0.0;
  double honesty_change = 0.0;
  soda::Divergence honesty_divergence;
};

void print_summary(const SimulateOptions& opt, const SimulateSummary& s) {
  const double px_per_frame = s.frames > 0 ? s.centroid_dx / static_cast<double>(s.frames) : 0.0;
  const double fps = s.wall_seconds > 0 ? static_cast<double>(s.frames) / s.wall_seconds : 0.0;
  if (opt.json) {
    nlohmann::json j = {{"model", opt.model},
                        {"frames", s.frames},
                        {"masses", s.masses},
                        {"links", s.links},
                        {"centroid_dx", s.centroid_dx},
                        {"centroid_dy", s.centroid_dy},
                        {"px_per_frame", px_per_frame},
                        {"wall_seconds", s.wall_seconds},
                        {"frames_per_second", fps},
                        {"stepping", s.stepping},
                        {"fixed_bars", s.bars},
                        {"bar_engine", s.bar_engine},
                        {"diverged", s.divergence.diverged}};
    if (s.divergence.diverged) {
      j["diverged_frame"] = s.divergence.frame;
      j["diverged_reason"] = s.divergence.reason;
    }
    if (s.honesty) {
      j["honesty_stepping"] = s.honesty_stepping;
      j["honesty_diverged"] = s.honesty_divergence.diverged;
      if (!s.honesty_divergence.diverged) {
        j["honesty_centroid_dx"] = s.honesty_centroid_dx;
        j["honesty_relative_change"] = s.honesty_change;
      }
    }
    std::cout << j.dump() << '\n';
    return;
  }
  std::printf("model               %s\n", opt.model.c_str());
  std::printf("stepping            %s\n", s.stepping.c_str());
  std::printf("frames              %lld\n", s.frames);
  if (s.divergence.diverged) {
    std::printf("DIVERGED            at frame %lld: %s (the run stopped there; the figures below are up to the\n"
                "                    last finite state)\n",
                s.divergence.frame, s.divergence.reason.c_str());
  }
  std::printf("masses              %d\n", s.masses);
  std::printf("links               %d (springs and muscles)\n", s.links);
  std::printf("fixed bars          %d (%s engine's rule%s)\n", s.bars, s.bar_engine.c_str(),
              s.bar_engine == "2003" ? ", SodaConstructor" : ", the racer's");
  std::printf("centroid dx, dy     %+.6f px, %+.6f px\n", s.centroid_dx, s.centroid_dy);
  std::printf("speed               %+.6f px/frame (%s)\n", px_per_frame,
              px_per_frame > 0 ? "walks right" : px_per_frame < 0 ? "walks left" : "stands");
  if (s.masses > 0) { // a walk is chaotic: this exact run is one draw of it
    std::printf("                    one exact run, as the original runs it; its spread: --replicas 16\n");
  }
  std::printf("wall time           %.6f s%s\n", s.wall_seconds, opt.trace.empty() ? "" : " (includes writing the trace)");
  std::printf("frames per second   %.0f\n", fps);
  if (s.honesty) {
    if (s.honesty_divergence.diverged) {
      std::printf("honesty             with %s the run diverged at frame %lld: %s\n", s.honesty_stepping.c_str(),
                  s.honesty_divergence.frame, s.honesty_divergence.reason.c_str());
    } else {
      std::printf("honesty             with %s: centroid dx %+.6f px, relative change %+.4f%s\n",
                  s.honesty_stepping.c_str(), s.honesty_centroid_dx, s.honesty_change,
                  std::fabs(s.honesty_change) > 0.1 ? " (more than 10 %: the walk depends on the step)" : "");
    }
  }
}

soda::BarEngine bar_engine_of(const SimulateOptions& opt) {
  soda::BarEngine engine{};
  if (!soda::parse_bar_engine(opt.bar_engine, engine)) {
    throw soda::InputError("--bar-engine: expected 2003 or 2004, got '" + opt.bar_engine + "'");
  }
  return engine;
}

/// A step's stability margin as JSON: +inf (no step is unstable) is null.
nlohmann::json finite_or_null(double v) { return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr); }

/// --stability: the predicted margin at the state as loaded and its minimum over
/// the run (core/stability.hpp), instead of the distance summary.
void run_stability(const SimulateOptions& opt) {
  const soda::LoadedModel loaded = soda::read_model_file(opt.model);
  for (const std::string& w : loaded.warnings) std::cerr << "sodaevo: warning: " << w << '\n';
  const soda::Model model = soda::build_model(loaded.def, bar_engine_of(opt));
  const soda::Stepping stepping = stepping_of(opt.stepping);
  const soda::StabilityAlongRun r = soda::stability_along_run(model, stepping, opt.frames, opt.stability_every);
  const soda::StabilityPrediction& p = r.first;
  if (opt.json) {
    const nlohmann::json j = {{"model", opt.model},
                              {"stepping", soda::stepping_label(stepping)},
                              {"omega_max", p.omega_max},
                              {"omega_max_squared", p.omega_max * p.omega_max},
                              {"dt", p.dt},
                              {"stable_dt", finite_or_null(p.stable_dt)},
                              {"margin", finite_or_null(p.margin)},
                              {"stable", p.margin > 1.0},
                              {"eigen_method", p.eigen.method},
                              {"frames", opt.frames},
                              {"samples", r.samples},
                              {"min_margin", finite_or_null(r.lowest.margin)},
                              {"min_margin_frame", r.lowest_frame}};
    std::cout << j.dump() << '\n';
    return;
  }
  auto number = [](double v) { return std::isfinite(v) ? soda::format_double_plain(v) : std::string("unlimited"); };
  std::printf("model               %s\n", opt.model.c_str());
  std::printf("stepping            %s (dt %s frame)\n", soda::stepping_label(stepping).c_str(), number(p.dt).c_str());
  std::printf("omega_max           %s rad/frame (omega_max^2 %s, largest eigenvalue of the stiffness, %s)\n",
              number(p.omega_max).c_str(), number(p.omega_max * p.omega_max).c_str(), p.eigen.method.c_str());
  std::printf("stable_dt           %s frame\n", number(p.stable_dt).c_str());
  std::printf("margin              %s (%s; (stable_dt/dt)^2, above 1 is stable)\n", number(p.margin).c_str(),
              p.margin > 1.0 ? "stable" : "UNSTABLE");
  std::printf("min margin          %s at frame %lld (%d samples, every %lld frames of %lld)\n",
              number(r.lowest.margin).c_str(), r.lowest_frame, r.samples, opt.stability_every, opt.frames);
}

void run_simulate(const SimulateOptions& opt) {
  if (opt.stability) {
    run_stability(opt);
    return;
  }
  soda::LoadedModel loaded = soda::read_model_file(opt.model);
  for (const std::string& w : loaded.warnings) std::cerr << "sodaevo: warning: " << w << '\n';
  const soda::BarEngine bar_engine = bar_engine_of(opt);
  const soda::Model model = soda::build_model(loaded.def, bar_engine);
  soda::State state = soda::make_state(model);
  const soda::Stepping stepping = stepping_of(opt.stepping);

  std::ofstream trace_file;
  std::optional<soda::TraceCsv> trace;
  if (!opt.trace.empty()) {
    trace_file.open(opt.trace, std::ios::binary | std::ios::trunc);
    if (!trace_file) throw soda::InputError(opt.trace + ": cannot open the trace file for writing");
    trace.emplace(trace_file, model);
    trace->write_row(state);
  }

  const soda::State initial = state;
  const soda::Point2 start = soda::mass_centroid(model, state);
  const auto t0 = std::chrono::steady_clock::now();
  soda::FrameCallback per_frame;
  if (trace) per_frame = [&](const soda::State& now) { trace->write_row(now); };
  const soda::Divergence divergence =
      soda::run_simulation(model, state, opt.frames, stepping, opt.energy_check, opt.reference, per_frame);
  const auto t1 = std::chrono::steady_clock::now();
  const soda::Point2 end = soda::mass_centroid(model, state);

  if (trace) {
    trace_file.flush();
    if (!trace_file) throw soda::InputError(opt.trace + ": writing the trace failed (disk full?)");
  }
  if (!opt.out.empty()) soda::write_model_file(opt.out, soda::def_with_state(loaded.def, model, state));

  SimulateSummary s;
  s.stepping = soda::stepping_label(stepping);
  s.bar_engine = soda::bar_engine_name(bar_engine);
  s.bars = model.bar_count();
  s.divergence = divergence;
  if (opt.honesty) {
    const soda::Stepping refined = sodaevo::refined_stepping(stepping, opt.honesty_factor);
    soda::State again = initial;
    s.honesty = true;
    s.honesty_stepping = soda::stepping_label(refined);
    s.honesty_divergence = soda::run_watched(model, again, divergence.diverged ? divergence.frame - 1 : opt.frames,
                                             refined, opt.energy_check, opt.reference);
    s.honesty_centroid_dx = soda::mass_centroid(model, again).x - start.x;
    s.honesty_change = sodaevo::relative_change(end.x - start.x, s.honesty_centroid_dx);
  }
  s.frames = divergence.diverged ? divergence.frame - 1 : opt.frames;
  s.masses = model.mass_count;
  s.links = model.link_count();
  s.centroid_dx = end.x - start.x;
  s.centroid_dy = end.y - start.y;
  s.wall_seconds = std::chrono::duration<double>(t1 - t0).count();
  print_summary(opt, s);
}

// --- simulate --replicas: the distribution of the distance over sine-jitter
// replicas (evolve/estimators/replica_ensemble.hpp) ---------------------------------------

void print_replica_summary(const SimulateOptions& opt, const std::string& stepping, const sodaevo::ReplicaResults& r) {
  std::vector<double> finite;
  for (double d : r.distances) {
    if (std::isfinite(d)) finite.push_back(d);
  }
  const int non_finite = static_cast<int>(r.distances.size() - finite.size());
  if (finite.empty()) throw soda::InputError(opt.model + ": every replica's run turned non-finite (the model blows up)");
  const sodaevo::SampleSummary s = sodaevo::summarize_sample(finite);
  if (opt.json) {
    nlohmann::json j = {{"model", opt.model},     {"stepping", stepping},
                        {"replicas", opt.replicas}, {"jitter", opt.jitter},
                        {"settle", opt.settle},     {"frames", opt.frames},
                        {"n", s.n},                 {"mean", s.mean},
                        {"median", s.median},       {"sd", s.sd},
                        {"min", s.min},             {"max", s.max},
                        {"interval95", {s.interval95_low, s.interval95_high}},
                        {"non_finite", non_finite}, {"distances", r.distances}};
    j["horizon"] = r.horizon >= 0 ? nlohmann::json(r.horizon) : nlohmann::json(nullptr);
    std::cout << j.dump() << '\n';
    return;
  }
  std::printf("model               %s\n", opt.model.c_str());
  std::printf("stepping            %s\n", stepping.c_str());
  std::printf("replicas            %d (replica 0 exact; replica r's sines moved by 1 ulp with p = %g, seed r)\n",
              opt.replicas, opt.jitter);
  std::printf("frames              %lld measured after %lld settling frames\n", opt.frames, opt.settle);
  if (non_finite > 0) std::printf("NON-FINITE          %d replicas blew up; the figures are over the others\n", non_finite);
  std::printf("distance            n %d, mean %+.6f px, median %+.6f px, sd %.6f px\n", s.n, s.mean, s.median, s.sd);
  std::printf("range               min %+.6f px, max %+.6f px\n", s.min, s.max);
  std::printf("interval95          [%+.6f, %+.6f] px (where one more replica falls 95 %% of the time)\n",
              s.interval95_low, s.interval95_high);
  if (r.horizon >= 0) {
    std::printf("horizon             frame %lld (the first at which replicas differ by more than %g px)\n", r.horizon,
                sodaevo::kHorizonTolerance);
  } else {
    std::printf("horizon             none: the replicas agree within %g px for all %lld frames\n",
                sodaevo::kHorizonTolerance, opt.settle + opt.frames);
  }
}

void run_simulate_replicas(const SimulateOptions& opt) {
  soda::LoadedModel loaded = soda::read_model_file(opt.model);
  for (const std::string& w : loaded.warnings) std::cerr << "sodaevo: warning: " << w << '\n';
  const soda::Model model = soda::build_model(loaded.def, bar_engine_of(opt));
  sodaevo::ReplicaSettings settings;
  settings.seeds = sodaevo::consecutive_seeds(opt.replicas);
  settings.probability = opt.jitter;
  settings.settle = opt.settle;
  settings.frames = opt.frames;
  settings.stepping = stepping_of(opt.stepping);
  print_replica_summary(opt, soda::stepping_label(settings.stepping), sodaevo::run_replicas(model, settings));
}

void add_replica_options(CLI::App* cmd, SimulateOptions& opt) {
  CLI::Option* replicas =
      cmd->add_option("--replicas", opt.replicas,
                      "Run K replicas, replica 0 exact and replica r with sine jitter of seed r, and report\n"
                      "the distribution of the centroid's x displacement (n, mean, median, sd, min, max,\n"
                      "interval95) and the predictability horizon (the first frame at which the replicas\n"
                      "differ by more than 1e-9 px). Steps with the reference step")
          ->check(CLI::Range(1, 10000));
  cmd->add_option("--jitter", opt.jitter,
                  "With --replicas: the share of sines a jittered replica moves by 1 ulp (default 0.002)")
      ->check(CLI::Range(0.0, 1.0))
      ->needs(replicas);
  cmd->add_option("--settle", opt.settle,
                  "With --replicas: frames run before the distance is measured over --frames (default 0)")
      ->check(CLI::Range(0LL, 1'000'000'000LL))
      ->needs(replicas);
  for (const char* other : {"--trace", "--out", "--honesty", "--energy-check"}) replicas->excludes(other);
}

} // namespace

void add_simulate_command(CLI::App& app) {
  auto opt = std::make_shared<SimulateOptions>();
  CLI::App* cmd = app.add_subcommand(
      "simulate",
      "Run a SodaConstructor model for N frames in the exact engine (one update per frame,\n"
      "as the original) or in the continuous mode, and report how far its centroid moved and\n"
      "how fast it ran.");
  cmd->add_option("model", opt->model, "Model to run (.xml, SodaConstructor v1 or v2)")
      ->required()
      ->check(non_empty_path())
      ->check(CLI::ExistingFile);
  cmd->add_option("--frames,-n", opt->frames, "Number of frames to simulate")
      ->default_val(1000)
      ->check(CLI::Range(0LL, 1'000'000'000'000LL));
  cmd->add_flag("--json", opt->json,
                "Print the summary as one JSON object (keys frames, masses, links, centroid_dx,\n"
                "centroid_dy, px_per_frame, wall_seconds, frames_per_second)");
  cmd->add_option("--trace", opt->trace,
                  "Write a CSV trace: one row per frame from 0 (as loaded) to N with\n"
                  "frame,wave_phase,wave_mode,x0,y0,vx0,vy0,x1,... for the free masses in file order");
  cmd->add_option("--out", opt->out, "Write the final state as canonical SodaConstructor v1 XML");
  cmd->add_flag("--reference", opt->reference,
                "Soda mode: use the plain reference step instead of the fast stepper (both give the\n"
                "same bits; the reference is the readable one, for checking)");
  add_stepping_options(cmd, opt->stepping);
  cmd->add_option("--bar-engine", opt->bar_engine,
                  "Fixed bars: 2003 (SodaConstructor's engine: every bar's box normalised) or 2004 (the\n"
                  "racer's copy: bars running downhill or right to left are practically never hit)")
      ->default_val("2003");
  cmd->add_flag("--energy-check", opt->energy_check,
                "Also flag runaway energy (more than the muscles can supply) as divergence, not only\n"
                "non-finite numbers. A diverged run stops at the last healthy frame and says why");
  cmd->add_flag("--honesty", opt->honesty,
                "Re-run with --honesty-factor times the sub-steps (soda: continuous Euler with that\n"
                "many) and report the relative change of the centroid's x displacement");
  cmd->add_option("--honesty-factor", opt->honesty_factor, "Sub-step multiplier of --honesty")
      ->default_val(4)
      ->check(CLI::Range(2, 64));
  add_replica_options(cmd, *opt);
  cmd->add_flag("--stability", opt->stability,
                "Instead of the distance: the predicted stability of the step (docs/stability.md):\n"
                "omega_max (fastest vibration, rad/frame), stable_dt (largest stable step, frames) and\n"
                "margin = (stable_dt/dt)^2 at the state as loaded, and the smallest margin sampled along\n"
                "--frames frames (JSON: omega_max, stable_dt, margin, min_margin; null = no limit)");
  cmd->add_option("--stability-every", opt->stability_every, "With --stability: sample every this many frames")
      ->default_val(10)
      ->check(CLI::Range(1LL, 1'000'000'000LL));
  cmd->callback([opt] {
    if (opt->replicas > 0 && !opt->stability) {
      run_simulate_replicas(*opt);
    } else {
      run_simulate(*opt); // --stability first: the prediction instead of a run
    }
  });
}

} // namespace sodaevo::app
