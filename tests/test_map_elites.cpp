// MAP-Elites: descriptors, the grid archive's cells, insertion and resampling
// rules, QD metrics, and the /map_elites config.
#include <catch2/catch.hpp>

#include <atomic>
#include <cmath>
#include <filesystem>

#include <nlohmann/json.hpp>

#include "core/input_error.hpp"
#include "core/model.hpp"
#include "core/step.hpp"
#include "evolve/described_evaluation.hpp"
#include "evolve/grid_archive.hpp"
#include "evolve/map_elites_config.hpp"
#include "evolve/map_elites_run.hpp"
#include "evolve/walk_problem.hpp"
#include "formats/atomic_file.hpp"
#include "formats/model_file.hpp"
#include "test_support.hpp"

using namespace sodaevo;

namespace {

double at(const Behaviour& b, Descriptor d) { return b[static_cast<std::size_t>(d)]; }

RunningEstimate estimate(long long n, double mean) {
  RunningEstimate e;
  e.n = n;
  e.mean = mean;
  return e;
}

} // namespace

TEST_CASE("descriptor meter: hand-computed extents, centroid height and floor contact", "[map-elites]") {
  soda::Model model;
  model.mass_count = 3;
  model.point_count = 3;
  model.link_muscle = {1, 0, 0};
  model.link_a = {0, 1, 0};
  model.link_b = {1, 2, 2};
  DescriptorMeter meter(model);
  soda::State s;
  s.x = {0, 4, 10};
  s.y = {0.5, 3, 1}; // min y 0.5: touching (within 1 px)
  meter.observe(s);
  s.x = {0, 2, 6};
  s.y = {2, 5, 8}; // in the air
  meter.observe(s);
  const Behaviour b = meter.behaviour();
  CHECK(at(b, Descriptor::MassCount) == 3);
  CHECK(at(b, Descriptor::MuscleShare) == Approx(1.0 / 3.0));
  CHECK(at(b, Descriptor::Width) == Approx((10.0 + 6.0) / 2));
  CHECK(at(b, Descriptor::Height) == Approx((2.5 + 6.0) / 2));
  CHECK(at(b, Descriptor::CentroidHeight) == Approx((4.5 / 3 + 15.0 / 3) / 2));
  CHECK(at(b, Descriptor::FloorContact) == 0.5);
  CHECK(meter.samples() == 2);
}

TEST_CASE("described evaluation: the fitness of evaluate_prepared_batch, descriptors sampled on the reference run",
          "[map-elites]") {
  RunConfig config = test::walker_run_config("d", 1, 4, 1, 300, 40);
  const soda::ModelDef walker = soda::read_model_file(test::models_dir() / "dainty_walker.xml").def;
  const WalkProblem problem(config);
  const soda::ModelDef prepared = problem.prepare(walker);
  const long long every = 7; // 300 = 42 * 7 + 6: the last sample comes after a shorter chunk
  const std::vector<DescribedEvaluation> described =
      evaluate_described_batch({&prepared, &prepared}, config.fitness, every);
  const Evaluation plain = problem.rollouts({&prepared}).front();
  REQUIRE(described.size() == 2);
  REQUIRE(described[0].evaluation.ok());
  CHECK(test::same_bits(described[0].evaluation.fitness, plain.fitness));
  CHECK(test::same_bits(described[1].evaluation.distance, plain.distance));

  // The reference stepper, one frame at a time, sampled at scored frames 7, 14, ..., 294, 300.
  const soda::Model model = soda::build_model(prepared);
  soda::State state = soda::make_state(model);
  soda::run(model, state, config.fitness.settle_frames);
  DescriptorMeter meter(model);
  for (long long f = 1; f <= config.fitness.frames; ++f) {
    soda::step(model, state);
    if (f % every == 0 || f == config.fitness.frames) meter.observe(state);
  }
  CHECK(meter.samples() == 43);
  for (std::size_t d = 0; d < kDescriptorCount; ++d) {
    INFO(descriptor_names()[d]);
    CHECK(test::same_bits(described[0].behaviour[d], meter.behaviour()[d]));
  }
  // The walker keeps its masses, stays on its feet and is wider than tall.
  CHECK(at(described[0].behaviour, Descriptor::MassCount) == static_cast<double>(walker.nodes.size()));
  CHECK(at(described[0].behaviour, Descriptor::FloorContact) == 1.0);
  CHECK(at(described[0].behaviour, Descriptor::Width) > at(described[0].behaviour, Descriptor::Height));
}

TEST_CASE("grid archive: cells are row-major, values outside a range clamp to the edge bins", "[map-elites]") {
  const GridArchive archive({{Descriptor::Width, 4, 0.0, 100.0},
                             {Descriptor::Height, 5, 10.0, 60.0},
                             {Descriptor::MassCount, 3, 2.5, 5.5}});
  CHECK(archive.cell_count() == 60);
  CHECK(archive.bin_of(0, 0.0) == 0);
  CHECK(archive.bin_of(0, 24.999) == 0);
  CHECK(archive.bin_of(0, 25.0) == 1);
  CHECK(archive.bin_of(0, 99.999) == 3);
  CHECK(archive.bin_of(0, 100.0) == 3);  // the top edge belongs to the last bin
  CHECK(archive.bin_of(0, 1e9) == 3);
  CHECK(archive.bin_of(0, -5.0) == 0);
  CHECK(archive.bin_of(0, NAN) == 0);
  CHECK(archive.bin_of(2, 4.0) == 1);    // 4 masses: the middle bin of 3, 4, 5
  // width 60 -> bin 2, height 35 -> bin 2, masses 5 -> bin 2: (2 * 5 + 2) * 3 + 2 = 38
  CHECK(archive.cell_of(std::vector<double>{60.0, 35.0, 5.0}) == 38);
  CHECK(archive.coordinates(38) == std::vector<int>{2, 2, 2});
  CHECK(archive.coordinates(59) == std::vector<int>{3, 4, 2});
  Behaviour b{};
  b[static_cast<std::size_t>(Descriptor::Width)] = 60.0;
  b[static_cast<std::size_t>(Descriptor::Height)] = 35.0;
  b[static_cast<std::size_t>(Descriptor::MassCount)] = 5.0;
  CHECK(archive.cell_of(b) == 38);
}

TEST_CASE("insertion rule: an empty cell takes the challenger; equal counts compare means", "[map-elites]") {
  CHECK(judge(nullptr, estimate(1, -50.0), 8).verdict == Verdict::Enter);
  const RunningEstimate elite = estimate(4, 100.0);
  CHECK(judge(&elite, estimate(4, 100.5), 8).verdict == Verdict::Replace);
  CHECK(judge(&elite, estimate(4, 100.0), 8).verdict == Verdict::Reject); // a tie keeps the elite
  CHECK(judge(&elite, estimate(4, 99.0), 8).verdict == Verdict::Reject);
  // Plain MAP-Elites: one replica each, cap 1.
  const RunningEstimate one = estimate(1, 10.0);
  CHECK(judge(&one, estimate(1, 11.0), 1).verdict == Verdict::Replace);
  CHECK(judge(&one, estimate(1, 9.0), 1).verdict == Verdict::Reject);
}

TEST_CASE("resampling rule: counts are made comparable before a challenger replaces an elite", "[map-elites]") {
  const RunningEstimate elite = estimate(16, 100.0);
  // A challenger on fewer replicas that looks better is sampled up to the elite's count...
  Judgement j = judge(&elite, estimate(4, 120.0), 32);
  CHECK(j.verdict == Verdict::SampleChallenger);
  CHECK(j.replicas == 12);
  // ... up to the cap only.
  j = judge(&elite, estimate(4, 120.0), 8);
  CHECK(j.verdict == Verdict::SampleChallenger);
  CHECK(j.replicas == 4);
  const RunningEstimate capped = estimate(8, 100.0);
  // A challenger that does not look better on what it has is rejected at once.
  CHECK(judge(&elite, estimate(4, 100.0), 32).verdict == Verdict::Reject);
  CHECK(judge(&elite, estimate(4, 80.0), 32).verdict == Verdict::Reject);
  // An elite on fewer replicas than the challenger gathers more first, whatever the means.
  const RunningEstimate young = estimate(2, 100.0);
  j = judge(&young, estimate(8, 50.0), 32);
  CHECK(j.verdict == Verdict::SampleElite);
  CHECK(j.replicas == 6);
  j = judge(&young, estimate(8, 150.0), 4);
  CHECK(j.verdict == Verdict::SampleElite);
  CHECK(j.replicas == 2);
  // Both at the cap: comparable.
  CHECK(judge(&capped, estimate(8, 101.0), 8).verdict == Verdict::Replace);
  CHECK(judge(&capped, estimate(12, 101.0), 8).verdict == Verdict::Replace);
}

TEST_CASE("running estimate: mean and sample sd of replicas", "[map-elites]") {
  RunningEstimate e;
  for (double v : {2.0, 4.0, 4.0, 4.0, 5.0, 5.0, 7.0, 9.0}) e.add(v);
  CHECK(e.n == 8);
  CHECK(e.mean == 5.0);
  CHECK(e.sd() == Approx(std::sqrt(32.0 / 7.0)));
  RunningEstimate one;
  one.add(3.0);
  CHECK(one.sd() == 0.0);
}

TEST_CASE("QD metrics of a hand-built archive", "[map-elites]") {
  GridArchive archive({{Descriptor::Width, 10, 0.0, 100.0}, {Descriptor::Height, 10, 0.0, 100.0}});
  const QdMetrics empty = archive.metrics(0.0);
  CHECK(empty.cells == 100);
  CHECK(empty.filled == 0);
  CHECK(empty.qd_score == 0.0);
  for (auto [cell, fitness] : std::vector<std::pair<std::size_t, double>>{{3, 50.0}, {17, 150.0}, {99, -20.0}}) {
    ArchiveEntry e;
    e.fitness = estimate(1, fitness);
    archive.place(cell, e);
  }
  const QdMetrics m = archive.metrics(0.0);
  CHECK(m.filled == 3);
  CHECK(m.coverage == 0.03);
  CHECK(m.qd_score == 200.0);  // the backward walker counts 0, not -20
  CHECK(m.normalized_qd_score == 2.0);
  CHECK(m.best == 150.0);
  CHECK(m.mean == Approx(60.0));
  const QdMetrics offset = archive.metrics(-100.0);
  CHECK(offset.qd_score == 150.0 + 250.0 + 80.0);
  CHECK(offset.normalized_qd_score == Approx(4.8));
  CHECK_THROWS(archive.place(100, ArchiveEntry{}));
}

namespace {

std::vector<ConfigProblem> problems_of(const std::string& text) {
  MapElitesConfig config;
  std::vector<ConfigProblem> problems;
  read_map_elites(nlohmann::json::parse(text), config, problems);
  return problems;
}

std::string first(const std::vector<ConfigProblem>& p) {
  return p.empty() ? std::string("(none)") : p.front().pointer + ": " + p.front().message;
}

} // namespace

TEST_CASE("/map_elites config: a full grid reads and writes back", "[map-elites]") {
  MapElitesConfig config;
  std::vector<ConfigProblem> problems;
  read_map_elites(nlohmann::json::parse(R"({"descriptors": ["muscle_share", "floor_contact"], "bins": [5, 4],
      "ranges": [[0, 1], [0, 1]], "batch_size": 10, "iterations": 3, "crossover_rate": 0.25,
      "snapshot_every": 0, "sample_every": 3, "qd_offset": -50})"),
                  config, problems);
  INFO(first(problems));
  REQUIRE(problems.empty());
  REQUIRE(config.axes.size() == 2);
  CHECK(config.axes[0] == GridAxis{Descriptor::MuscleShare, 5, 0.0, 1.0});
  CHECK(config.axes[1] == GridAxis{Descriptor::FloorContact, 4, 0.0, 1.0});
  CHECK(config.batch_size == 10);
  CHECK(config.qd_offset == -50.0);
  MapElitesConfig back;
  read_map_elites(to_json(config), back, problems);
  CHECK(problems.empty());
  CHECK(back == config);
  // The default grid: 3 axes, 1,000 to 2,000 cells.
  const MapElitesConfig defaults;
  std::size_t cells = 1;
  for (const GridAxis& a : defaults.axes) cells *= static_cast<std::size_t>(a.bins);
  CHECK(defaults.axes.size() == 3);
  CHECK(cells >= 1000);
  CHECK(cells <= 2000);
}

TEST_CASE("/map_elites config: bad input names the pointer, what was expected and what was found", "[map-elites]") {
  const std::string grid = R"("bins": [4, 4], "ranges": [[0, 1], [0, 1]])";
  auto p = problems_of(R"({"descriptors": ["width", "wingspan"], )" + grid + "}");
  CHECK(first(p) == "/map_elites/descriptors/1: expected one of mass_count, muscle_share, width, height, "
                    "centroid_height, floor_contact, got \"wingspan\"");
  p = problems_of(R"({"descriptors": ["width", "height"], "bins": [4, 0], "ranges": [[0, 1], [0, 1]]})");
  CHECK(first(p) == "/map_elites/bins/1: expected an integer in [1, 100000], got 0");
  p = problems_of(R"({"descriptors": ["width", "height"], "bins": [4, 4], "ranges": [[0, 1], [5, 5]]})");
  CHECK(first(p) == "/map_elites/ranges/1: expected lo < hi (a range that is neither empty nor inverted), got [5,5]");
  p = problems_of(R"({"descriptors": ["width", "height"], "bins": [4, 4], "ranges": [[3, 1], [0, 1]]})");
  CHECK(first(p) == "/map_elites/ranges/0: expected lo < hi (a range that is neither empty nor inverted), got [3,1]");
  p = problems_of(R"({"descriptors": ["width", "height", "mass_count"], "bins": [100, 100, 11],
                      "ranges": [[0, 1], [0, 1], [0, 1]]})");
  CHECK(first(p) == "/map_elites/bins: expected at most 100000 cells (the bins multiplied), got 110000 from "
                    "[100,100,11]");
  p = problems_of(R"({"batch_size": 0})");
  CHECK(first(p) == "/map_elites/batch_size: expected an integer in [1, 100000], got 0");
  p = problems_of(R"({"descriptors": ["width"], "bins": [4], "ranges": [[0, 1]]})");
  CHECK(first(p).rfind("/map_elites/descriptors: expected an array of 2 or 3 descriptor names", 0) == 0);
  p = problems_of(R"({"descriptors": ["width", "width"], )" + grid + "}");
  CHECK(first(p) == "/map_elites/descriptors/1: expected a descriptor not named before, got \"width\"");
  p = problems_of(R"({"descriptors": ["width", "height"], "bins": [4, 4, 4], "ranges": [[0, 1], [0, 1]]})");
  CHECK(first(p) == "/map_elites/bins: expected an array of 2 integers (one per descriptor), got [4,4,4]");
  p = problems_of(R"({"descriptors": ["width", "height"], "bins": [4, 4]})");
  CHECK(first(p) == "/map_elites/ranges: expected an array (descriptors, bins and ranges are given together), "
                    "got nothing");
  p = problems_of(R"({"batch": 3})");
  CHECK(first(p).rfind("/map_elites/batch: unknown key (expected one of: descriptors, ", 0) == 0);
  p = problems_of(R"([1])");
  CHECK(first(p).rfind("/map_elites: expected an object with keys", 0) == 0);
}

namespace {

/// A small MAP-Elites run: the walker and random creatures, 2 descriptors.
struct SmallRun {
  RunConfig config = test::walker_run_config("me", 7, 12, 1, 300, 40);
  MapElitesConfig me;
  SmallRun() {
    me.axes = {{Descriptor::Width, 6, 0.0, 240.0}, {Descriptor::MassCount, 6, 2.5, 14.5}};
    me.iterations = 4;
    me.batch_size = 10;
    me.crossover_rate = 0.3;
    me.snapshot_every = 2;
    me.sample_every = 5;
    config.save.checkpoint_every = 1;
  }
};

std::filesystem::path run_dir(const std::string& name) {
  return test::fresh_temp_dir("map_elites_" + name);
}

std::string text_of(const std::filesystem::path& p) { return soda::read_whole_file(p); }

} // namespace

TEST_CASE("MAP-Elites run: the same archive on 1 and 2 threads, and resumed after a stop", "[map-elites]") {
  const SmallRun run;
  const auto one = run_dir("one"), two = run_dir("two"), stopped = run_dir("stopped");
  const MapElitesOutcome a =
      run_map_elites(one, run.config, run.me, described_evaluator_on_threads(run.config, run.me, 1), {});
  const MapElitesOutcome b =
      run_map_elites(two, run.config, run.me, described_evaluator_on_threads(run.config, run.me, 2), {});
  CHECK(a.stopped_because == "completed");
  CHECK(a.last_iteration == 4);
  CHECK(a.evaluations == 12 + 4 * 10);
  CHECK(a.metrics.filled > 3);
  CHECK(text_of(one / "qd.csv") == text_of(two / "qd.csv"));
  CHECK(text_of(one / "archive.json") == text_of(two / "archive.json"));

  // Stopped after iteration 2 (as Ctrl-C stops it), then resumed to the end.
  std::atomic<bool> stop{false};
  MapElitesOptions options;
  options.stop_requested = &stop;
  options.on_iteration = [&](const MapElitesProgress& p) {
    if (p.iteration == 2) stop = true;
  };
  const auto evaluator = described_evaluator_on_threads(run.config, run.me, 2);
  const MapElitesOutcome first = run_map_elites(stopped, run.config, run.me, evaluator, options);
  CHECK(first.stopped_because == "interrupted");
  CHECK(first.last_iteration == 2);
  const MapElitesOutcome rest = run_map_elites(stopped, run.config, run.me, evaluator, {});
  CHECK(rest.last_iteration == 4);
  CHECK(text_of(one / "qd.csv") == text_of(stopped / "qd.csv"));
  CHECK(text_of(one / "archive.json") == text_of(stopped / "archive.json"));
  CHECK(text_of(one / "archive_checkpoint.json").substr(0, 200) ==
        text_of(stopped / "archive_checkpoint.json").substr(0, 200));

  // Every elite is written, and each reads back as a model that evaluates to its logged distance.
  const nlohmann::json archive = nlohmann::json::parse(text_of(one / "archive.json"));
  REQUIRE(archive["cells"].size() == a.metrics.filled);
  for (const auto& cell : archive["cells"]) {
    const soda::ModelDef prepared = soda::read_model_file(one / cell["file"].get<std::string>()).def;
    const Evaluation e = WalkProblem(run.config).rollouts({&prepared}).front();
    CHECK(e.distance == cell["distance"].get<double>());
  }
  CHECK(std::filesystem::exists(one / "snapshots" / "archive_00000.json"));
  CHECK(std::filesystem::exists(one / "snapshots" / "archive_00002.json"));
  CHECK(std::filesystem::exists(one / "snapshots" / "archive_00004.json"));
}

TEST_CASE("run config: /algorithm and /map_elites read, resolve and round-trip; misuse names the pointer",
          "[map-elites][config]") {
  const RunConfig c = parse_run_config(R"({"algorithm": "map-elites", "map_elites": {"batch_size": 7,
      "descriptors": ["floor_contact", "centroid_height"], "bins": [3, 9], "ranges": [[0, 1], [0, 90]]}})",
                                       "me.json", "/nowhere");
  CHECK(c.algorithm == AlgorithmKind::MapElites);
  CHECK(c.map_elites.batch_size == 7);
  REQUIRE(c.map_elites.axes.size() == 2);
  CHECK(c.map_elites.axes[1] == GridAxis{Descriptor::CentroidHeight, 9, 0.0, 90.0});
  CHECK(parse_run_config(to_json(c).dump(), "resolved", "/nowhere") == c);
  // A GA run's resolved config names neither key (its run folder is as before).
  const nlohmann::json ga = to_json(parse_run_config("{}", "ga.json", "/nowhere"));
  CHECK(!ga.contains("algorithm"));
  CHECK(!ga.contains("map_elites"));
  const auto error_of = [](const std::string& text) {
    try {
      parse_run_config(text, "x.json", "/nowhere");
    } catch (const soda::InputError& e) {
      return std::string(e.what());
    }
    return std::string("(no error)");
  };
  CHECK(error_of(R"({"algorithm": "cma-es"})") == "x.json: /algorithm: expected one of \"ga\" or \"map-elites\", got \"cma-es\"");
  CHECK(error_of(R"({"map_elites": {"batch_size": 3}})") ==
        "x.json: /map_elites: expected only with /algorithm \"map-elites\", got it with the GA");
  CHECK(error_of(R"({"algorithm": "map-elites", "map_elites": {"batch_size": 0}})") ==
        "x.json: /map_elites/batch_size: expected an integer in [1, 100000], got 0");
  CHECK_THAT(error_of(R"({"algorithm": "map-elites", "fitness": {"mode": "continuous"}})"),
             Catch::StartsWith("x.json: /algorithm: expected \"ga\" with /fitness/mode \"continuous\""));
}
