#include <chrono>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <memory>
#include <optional>
#include <string>

#include <nlohmann/json.hpp>

#include "app/commands.hpp"
#include "core/input_error.hpp"
#include "core/model.hpp"
#include "core/model_file.hpp"
#include "core/fast_step.hpp"
#include "core/step.hpp"
#include "core/trace_csv.hpp"

namespace sodaevo::app {

namespace {

struct SimulateOptions {
  std::string model;
  long long frames = 1000;
  bool json = false;
  std::string trace;
  std::string out;
  bool reference = false;
};

struct SimulateSummary {
  long long frames = 0;
  int masses = 0;
  int links = 0;
  double centroid_dx = 0.0;
  double centroid_dy = 0.0;
  double wall_seconds = 0.0;
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
                        {"frames_per_second", fps}};
    std::cout << j.dump() << '\n';
    return;
  }
  std::printf("model               %s\n", opt.model.c_str());
  std::printf("frames              %lld\n", s.frames);
  std::printf("masses              %d\n", s.masses);
  std::printf("links               %d (springs and muscles)\n", s.links);
  std::printf("centroid dx, dy     %+.6f px, %+.6f px\n", s.centroid_dx, s.centroid_dy);
  std::printf("speed               %+.6f px/frame (%s)\n", px_per_frame,
              px_per_frame > 0 ? "walks right" : px_per_frame < 0 ? "walks left" : "stands");
  std::printf("wall time           %.6f s%s\n", s.wall_seconds, opt.trace.empty() ? "" : " (includes writing the trace)");
  std::printf("frames per second   %.0f\n", fps);
}

void run_simulate(const SimulateOptions& opt) {
  soda::LoadedModel loaded = soda::read_model_file(opt.model);
  for (const std::string& w : loaded.warnings) std::cerr << "sodaevo: warning: " << w << '\n';
  const soda::Model model = soda::build_model(loaded.def);
  soda::State state = soda::make_state(model);

  std::ofstream trace_file;
  std::optional<soda::TraceCsv> trace;
  if (!opt.trace.empty()) {
    trace_file.open(opt.trace, std::ios::binary | std::ios::trunc);
    if (!trace_file) throw soda::InputError(opt.trace + ": cannot open the trace file for writing");
    trace.emplace(trace_file, model);
    trace->write_row(state);
  }

  const soda::Point2 start = soda::mass_centroid(model, state);
  const auto t0 = std::chrono::steady_clock::now();
  if (opt.reference) {
    for (long long f = 0; f < opt.frames; ++f) {
      soda::step(model, state);
      if (trace) trace->write_row(state);
    }
  } else {
    // Same bits as the reference step, faster (core/fast_step.hpp).
    soda::FastStepper stepper(model, opt.frames);
    if (trace) {
      for (long long f = 0; f < opt.frames; ++f) {
        stepper.step(state);
        trace->write_row(state);
      }
    } else {
      stepper.run(state, opt.frames);
    }
  }
  const auto t1 = std::chrono::steady_clock::now();
  const soda::Point2 end = soda::mass_centroid(model, state);

  if (trace) {
    trace_file.flush();
    if (!trace_file) throw soda::InputError(opt.trace + ": writing the trace failed (disk full?)");
  }
  if (!opt.out.empty()) soda::write_model_file(opt.out, soda::def_with_state(loaded.def, model, state));

  SimulateSummary s;
  s.frames = opt.frames;
  s.masses = model.mass_count;
  s.links = model.link_count();
  s.centroid_dx = end.x - start.x;
  s.centroid_dy = end.y - start.y;
  s.wall_seconds = std::chrono::duration<double>(t1 - t0).count();
  print_summary(opt, s);
}

} // namespace

void add_simulate_command(CLI::App& app) {
  auto opt = std::make_shared<SimulateOptions>();
  CLI::App* cmd = app.add_subcommand(
      "simulate",
      "Run a SodaConstructor model for N frames in the exact engine (one update per frame,\n"
      "as the original) and report how far its centroid moved and how fast it ran.");
  cmd->add_option("model", opt->model, "Model to run (.xml, SodaConstructor v1 or v2)")
      ->required()
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
                "Use the plain reference step instead of the fast stepper (both give the same\n"
                "bits; the reference is the readable one, for checking)");
  cmd->callback([opt] { run_simulate(*opt); });
}

} // namespace sodaevo::app
