// `sodaevo bench races`: the 880 golden race results of the original racer, raced
// again (bench/golden_races.hpp); writes results/bench/races.md.
#include <chrono>
#include <cstdio>
#include <iostream>
#include <memory>

#include "app/commands.hpp"
#include "bench/golden_races.hpp"
#include "formats/atomic_file.hpp"

namespace sodaevo::app {

namespace {

struct BenchRacesOptions {
  std::string data = "tests/data";
  std::string out = "results/bench";
  std::string race_filter;
  bool speed = true;
};

void run_bench_races(const BenchRacesOptions& opt) {
  const auto t0 = std::chrono::steady_clock::now();
  const std::vector<bench::GoldenRace> races = bench::race_golden(opt.data, opt.race_filter);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  std::string report = "# Golden races (sodaevo bench races)\n\nThe results of the original racer (" + opt.data +
                       "/terrain/races.tsv) raced again with `sodaevo race`'s lane, in " +
                       std::to_string(static_cast<int>(seconds)) + " s.\n\n" + bench::golden_races_report(races);
  if (opt.speed) {
    const std::filesystem::path data(opt.data);
    const auto speed = bench::measure_lane_speed(data / "soda/wwagner4_wodka/lib_wodka_jar/terrain/TerrainFlat.xml",
                                                 data / "terrain/contenders/dw_v1_wavereverse.xml", 10000, 5);
    char text[1200];
    std::snprintf(text, sizeof text,
                  "\n## Lane speed\n\nThe Dainty Walker (wave reversed) in the TerrainFlat lane, FastStepper, best of 5 "
                  "alternated runs of 10,000 frames: %.0f frames/s with the lane's bars, %.0f frames/s in the same "
                  "lane model without its bars (on the container floor): **%.2fx**. With every mass one by one in "
                  "file order (FastStepOptions::force_ordered, the kernel bars took before): %.0f frames/s (%.2fx).\n\n"
                  "Where the time goes: the masses move in SIMD as on the floor, then the bar rules run for the "
                  "masses a bar remembers and those whose move may touch a bar: %.2f of the %d masses per frame "
                  "(the walker's feet on the bar). The lane costs %.0f ns per frame more than the floor: %.0f ns "
                  "per mass that takes the rules, all of it counted (the rules' own arithmetic: crossing point with two divisions, "
                  "slide, joint test, velocity, each on the chain of the one before).\n",
                  speed.lane_fps, speed.floor_fps, speed.ratio(), speed.ordered_fps,
                  speed.floor_fps > 0.0 ? speed.ordered_fps / speed.floor_fps : 0.0, speed.rules_per_frame, speed.masses,
                  speed.extra_ns(), speed.rules_per_frame > 0.0 ? speed.extra_ns() / speed.rules_per_frame : 0.0);
    report += text;
    const auto fused = bench::measure_fused_lanes(data / "soda/wwagner4_wodka/lib_wodka_jar/terrain/TerrainFlat.xml",
                                                  data / "terrain/contenders", 2000, 5);
    std::snprintf(
        text, sizeof text,
        "\n## Fused lanes\n\nThe %d golden contenders (the Dainty Walker and 40 random walkers), each in its own "
        "TerrainFlat lane, best of 5 alternated runs. Stepped 2,000 frames: %.2fM lane-frames/s one by one (a "
        "FastStepper each), %.2fM fused (BatchStepper: different creatures with their bars in one scene), "
        "**%.2fx**. The same lane models without their bars: %.2fM one by one, %.2fM fused (%.2fx); fused lanes "
        "against fused floors: **%.2fx**. Their races (timeout 10,000, %lld updates in all): %.3f s one by one "
        "(run_race_fast), %.3f s together (run_races_together), **%.2fx**.\n\n"
        "Why fusing gains little here: fusing shares the SIMD batches of the links and masses and the frame's "
        "overhead, but not the bar rules, which run mass by mass on their own arithmetic and are most of a "
        "lane-frame's time (above).\n",
        fused.lanes, fused.alone_fps / 1e6, fused.fused_fps / 1e6,
        fused.alone_fps > 0.0 ? fused.fused_fps / fused.alone_fps : 0.0, fused.floor_alone_fps / 1e6,
        fused.floor_fused_fps / 1e6, fused.floor_alone_fps > 0.0 ? fused.floor_fused_fps / fused.floor_alone_fps : 0.0,
        fused.floor_fused_fps > 0.0 ? fused.fused_fps / fused.floor_fused_fps : 0.0, fused.race_frames,
        fused.races_alone_s, fused.races_fused_s, fused.races_fused_s > 0.0 ? fused.races_alone_s / fused.races_fused_s : 0.0);
    report += text;
  }
  std::cout << report;
  if (opt.race_filter.empty()) {
    std::filesystem::create_directories(opt.out);
    soda::write_file_atomically(std::filesystem::path(opt.out) / "races.md", report);
    std::cerr << "bench races: wrote " << (std::filesystem::path(opt.out) / "races.md").string() << "\n";
  }
}

} // namespace

void add_bench_races_command(CLI::App& bench) {
  auto opt = std::make_shared<BenchRacesOptions>();
  CLI::App* cmd = bench.add_subcommand(
      "races", "The original racer's 880 golden race results (20 race files x 44 contenders), raced again:\n"
               "how many agree to the last bit, and each difference with its diagnosis. Writes races.md.");
  cmd->add_option("--data", opt->data, "Folder holding soda/ and terrain/ (the golden data)")->default_val(opt->data);
  cmd->add_option("--out", opt->out, "Output directory")->default_val(opt->out);
  cmd->add_flag("!--no-speed", opt->speed, "Skip the lane speed measurement");
  cmd->add_option("--race", opt->race_filter, "Only race files whose path contains this (prints, writes nothing)");
  cmd->callback([opt] { run_bench_races(*opt); });
}

} // namespace sodaevo::app
