// The sodaevo command line as a user runs it: the built binary, real files.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "formats/atomic_file.hpp"
#include "formats/model_file.hpp"
#include "test_support.hpp"

using namespace sodaevo::test;
namespace fs = std::filesystem;

namespace {

/// A CSV file as its header line and its data lines.
struct CsvLines {
  std::string header;
  std::vector<std::string> rows;
};
CsvLines read_csv_lines(const fs::path& path) {
  std::istringstream csv(soda::read_whole_file(path));
  CsvLines lines;
  std::getline(csv, lines.header);
  for (std::string line; std::getline(csv, line);) lines.rows.push_back(line);
  return lines;
}

/// The cells of one CSV line (no quoting in the files tested here).
std::vector<std::string> csv_cells(const std::string& line) {
  std::vector<std::string> cells;
  std::istringstream in(line);
  for (std::string c; std::getline(in, c, ',');) cells.push_back(c);
  return cells;
}

/// The cells of one CSV line as numbers.
std::vector<double> csv_numbers(const std::string& line) {
  std::vector<double> numbers;
  for (const std::string& c : csv_cells(line)) numbers.push_back(std::stod(c));
  return numbers;
}

} // namespace

TEST_CASE("simulate --json reports the summary keys and the walk", "[cli]") {
  const fs::path model = golden_dir() / "dw_v1_wide100000_noautorev.xml";
  const ShellResult r = run_sodaevo("simulate " + model.string() + " --frames 10000 --json");
  INFO(r.output);
  REQUIRE(r.exit_code == 0);
  const auto j = nlohmann::json::parse(r.output);
  for (const char* key : {"frames", "masses", "links", "centroid_dx", "px_per_frame", "wall_seconds", "frames_per_second"}) {
    CHECK(j.contains(key));
  }
  CHECK(j["frames"] == 10000);
  CHECK(j["masses"] == 10);
  // golden/README.md: the v1 Dainty Walker moves -7503.66 px in 10,000 frames.
  CHECK(j["centroid_dx"].get<double>() == Approx(-7503.66).margin(1.0));
  CHECK(j["px_per_frame"].get<double>() == Approx(-0.750366).margin(1e-4));
  CHECK(j["frames_per_second"].get<double>() > 0);
}

TEST_CASE("simulate --trace writes the golden trace's columns", "[cli]") {
  const fs::path dir = fresh_temp_dir("cli_trace");
  const fs::path csv = dir / "trace.csv";
  const ShellResult r = run_sodaevo("simulate " + (golden_dir() / "random_5.xml").string() +
                                    " --frames 300 --trace " + csv.string());
  INFO(r.output);
  REQUIRE(r.exit_code == 0);
  const auto golden = read_golden_trace(golden_dir() / "random_5.trace.txt");
  std::ifstream in(csv);
  std::string line;
  REQUIRE(std::getline(in, line));
  CHECK(line.rfind("frame,wave_phase,wave_mode,x0,y0,vx0,vy0,x1,", 0) == 0);
  int frame = 0;
  while (std::getline(in, line)) {
    const std::vector<double> fields = csv_numbers(line);
    REQUIRE(fields.size() == 3 + golden[frame].values.size());
    CHECK(fields[0] == frame);
    CHECK(fields[2] == golden[frame].wave_mode);
    for (size_t k = 0; k < golden[frame].values.size(); ++k) {
      REQUIRE(std::fabs(fields[3 + k] - golden[frame].values[k]) <= 1e-5);
    }
    ++frame;
  }
  CHECK(frame == 301);
  fs::remove_all(dir);
}

TEST_CASE("simulate --out writes a final state that reloads and continues exactly", "[cli]") {
  const fs::path dir = fresh_temp_dir("cli_out");
  const fs::path model = golden_dir() / "random_16.xml";
  const fs::path mid = dir / "mid.xml";
  REQUIRE(run_sodaevo("simulate " + model.string() + " --frames 100 --out " + mid.string()).exit_code == 0);
  REQUIRE(run_sodaevo("simulate " + mid.string() + " --frames 50 --trace " + (dir / "b.csv").string()).exit_code == 0);
  // Frames 100..150 continued from the saved state follow the golden rows. Not to
  // the bit: the writer regroups links (springs before muscles), which changes the
  // order of additions (docs/physics.md); the saved numbers themselves are exact.
  const auto golden = read_golden_trace(golden_dir() / "random_16.trace.txt");
  std::ifstream in(dir / "b.csv");
  std::string line;
  std::getline(in, line);
  int row = 0;
  while (std::getline(in, line)) {
    const std::vector<double> fields = csv_numbers(line);
    const auto& gold = golden[100 + row];
    REQUIRE(fields.size() == 3 + gold.values.size());
    for (size_t k = 0; k < gold.values.size(); ++k) REQUIRE(std::fabs(fields[3 + k] - gold.values[k]) <= 1e-9);
    ++row;
  }
  CHECK(row == 51);
  fs::remove_all(dir);
}

TEST_CASE("convert turns a v2 model into canonical v1 that loads the same", "[cli]") {
  const fs::path dir = fresh_temp_dir("cli_convert");
  const fs::path in = data_dir() / "soda" / "KeniF_SodaSumo" / "carefulslug.xml";
  const fs::path out = dir / "carefulslug.xml";
  const ShellResult r = run_sodaevo("convert " + in.string() + " " + out.string());
  INFO(r.output);
  REQUIRE(r.exit_code == 0);
  const std::string text = soda::read_whole_file(out);
  CHECK(text.rfind("<?xml version=\"1.0\" encoding=\"ISO-8859-1\" standalone=\"no\"?>\n<!DOCTYPE sodaconstructor>\n<model>\n", 0) == 0);
  const soda::LoadedModel v2 = soda::read_model_file(in);
  const soda::LoadedModel v1 = soda::read_model_file(out);
  CHECK(v1.format == soda::ModelFormat::V1);
  CHECK(v1.def == soda::canonical_form(v2.def));
  fs::remove_all(dir);
}

TEST_CASE("bad input: clear message with file and line, non-zero exit, no crash", "[cli]") {
  const fs::path dir = fresh_temp_dir("cli_bad_input");
  const fs::path bad = dir / "bad.xml";
  std::ofstream(bad) << "<model>\n<nodes>\n<mass id=\"m0\" x=\"1\" y=\"2\" vx=\"0\" vy=\"0\"/>\n</nodes>\n<links>\n"
                        "<spring a=\"m0\" b=\"m9\" restlength=\"3\"/>\n</links>\n</model>\n";
  ShellResult r = run_sodaevo("simulate " + bad.string());
  CHECK(r.exit_code != 0);
  CHECK(r.output.find(bad.string() + ":6:") != std::string::npos);
  CHECK(r.output.find("m9") != std::string::npos);

  std::ofstream(bad, std::ios::trunc) << "<model><nodes><mass id=\"m0\" x=\"1\"";
  r = run_sodaevo("simulate " + bad.string());
  CHECK(r.exit_code != 0);
  CHECK(r.output.find(bad.string() + ":1:") != std::string::npos);

  r = run_sodaevo("simulate " + (data_dir() / "soda" / "wwagner4_wodka" / "doc" / "res" / "race_hist_11_166.xml").string());
  CHECK(r.exit_code != 0);
  CHECK(r.output.find("race") != std::string::npos);

  r = run_sodaevo("simulate " + (dir / "does_not_exist.xml").string());
  CHECK(r.exit_code != 0);
  CHECK(r.output.find("does_not_exist.xml") != std::string::npos);

  r = run_sodaevo("simulate " + (golden_dir() / "random_5.xml").string() + " --frames -3");
  CHECK(r.exit_code != 0);

  // An empty path is named as such (it once printed ": cannot open model file").
  for (const std::string command : {"simulate ''", "render '' -o x.svg", "convert '' x.xml", "report ''"}) {
    r = run_sodaevo(command);
    INFO(command << ": " << r.output);
    CHECK(r.exit_code != 0);
    CHECK(r.output.find(": expected a path, got an empty one") != std::string::npos);
  }
  fs::remove_all(dir);
}

TEST_CASE("bench evolve compares the three search methods at equal evaluations", "[cli]") {
  const fs::path out = fresh_temp_dir("cli_bench_evolve");
  const fs::path root = fs::path(SODAEVO_MODELS_DIR).parent_path();
  const ShellResult r = run_sodaevo("bench evolve --config " + (root / "configs" / "quick.json").string() +
                                    " --classic " + (root / "models" / "dainty_walker.xml").string() +
                                    " --generations 2 --seeds 2 --skip-full-run --out " + out.string());
  INFO(r.output);
  REQUIRE(r.exit_code == 0);
  // One row per method and seed, all at the same evaluation count: the GA's two
  // generations of 24 minus the 2 elites it does not re-evaluate.
  const CsvLines csv = read_csv_lines(out / "evolve.csv");
  CHECK(csv.header.rfind("method,seed,evaluations,", 0) == 0);
  std::map<std::string, int> per_method;
  for (const std::string& line : csv.rows) {
    per_method[line.substr(0, line.find(','))]++;
    CHECK(line.find(",46,") != std::string::npos);
  }
  CHECK(csv.rows.size() == 6);
  CHECK(per_method == std::map<std::string, int>{{"ga", 2}, {"hill", 2}, {"random", 2}});
  CHECK(soda::read_whole_file(out / "evolve.svg").find("<svg") != std::string::npos);
  CHECK(soda::read_whole_file(out / "evolve.md").find("Dainty Walker under the same fitness settings") != std::string::npos);
  fs::remove_all(out);
}

TEST_CASE("bench speed: the ga section without a saved run, or without generations, is a clear error", "[cli]") {
  const fs::path out = fresh_temp_dir("cli_bench_speed_no_run");
  const ShellResult asked = run_sodaevo("bench speed --quick --sections ga --ga-run " + (out / "no_such_run").string());
  INFO(asked.output);
  CHECK(asked.exit_code != 0);
  CHECK(asked.output.find((out / "no_such_run").string() + ": no saved run here (config.json missing)") !=
        std::string::npos);
  // A run directory without its generations: named too.
  fs::create_directories(out / "empty_run");
  // A config that reads (its seed model found), in a folder with no generations.
  fs::create_directories(out / "models");
  fs::copy_file(fs::path(SODAEVO_MODELS_DIR) / "dainty_walker.xml", out / "models" / "dainty_walker.xml");
  fs::copy_file(fs::path(SODAEVO_MODELS_DIR).parent_path() / "configs" / "quick.json", out / "empty_run" / "config.json");
  const ShellResult empty = run_sodaevo("bench speed --quick --sections ga --ga-run " + (out / "empty_run").string());
  INFO(empty.output);
  CHECK(empty.exit_code != 0);
  CHECK(empty.output.find("empty_run: the run has no saved generation") != std::string::npos);
  fs::remove_all(out);
}

TEST_CASE("bench speed --quick writes every engine's row, the population ratios and the files", "[cli]") {
  const fs::path out = fresh_temp_dir("cli_bench_speed");
  const fs::path root = fs::path(SODAEVO_MODELS_DIR).parent_path();
  // A small saved run for the GA section: 3 generations of 24, all saved.
  const fs::path ga_run = out / "ga_run";
  {
    std::ofstream config(out / "ga.json");
    config << R"({"name": "ga", "seed": 3, "generations": 3,
      "population": {"size": 24, "seed_models": [")"
           << (root / "models" / "dainty_walker.xml").string() << R"("], "random_fraction": 0.5},
      "fitness": {"frames": 300, "settle_frames": 50},
      "save": {"generation_every": 1, "checkpoint_every": 1}})";
  }
  const ShellResult evolved = run_sodaevo("evolve " + (out / "ga.json").string() + " --quiet --out " + ga_run.string());
  INFO(evolved.output);
  REQUIRE(evolved.exit_code == 0);
  {
    // The summary names what the best's fitness stands on and what fresh replicas
    // gave it, as champions.json records them (its first entry is the best).
    const nlohmann::json champions = nlohmann::json::parse(soda::read_whole_file(ga_run / "champions.json"));
    REQUIRE(!champions.empty());
    const nlohmann::json& best = champions[0];
    char median[64];
    std::snprintf(median, sizeof median, "%.2f", best["check"]["median"].get<double>());
    CHECK(evolved.output.find("champion     " + best["id"].get<std::string>() + " (best of the last generation)  fitness ") !=
          std::string::npos);
    CHECK(evolved.output.find(" of " + std::to_string(best["selection"]["n"].get<int>()) + " replicas, sd ") !=
          std::string::npos);
    CHECK(evolved.output.find("checked on " + std::to_string(best["check"]["n"].get<int>()) +
                              " fresh replicas: median " + median + " px") != std::string::npos);
  }
  {
    // The progress lines count generations from 1, as the page and the report do
    // (the ids and files keep counting from 0).
    const ShellResult loud = run_sodaevo("evolve " + (out / "ga.json").string() + " --out " + (out / "ga-loud").string());
    INFO(loud.output);
    REQUIRE(loud.exit_code == 0);
    CHECK(loud.output.find("gen 1/3 ") != std::string::npos);
    CHECK(loud.output.find("gen 3/3 ") != std::string::npos);
    CHECK(loud.output.find("gen 0/") == std::string::npos);
    CHECK(loud.output.find("after generation 3 (") != std::string::npos);
  }
  const ShellResult r = run_sodaevo("bench speed --quick --threads 2 --models " + (root / "models").string() +
                                    " --ga-run " + ga_run.string() + " --out " + out.string());
  INFO(r.output);
  REQUIRE(r.exit_code == 0);
  const CsvLines csv = read_csv_lines(out / "speed.csv");
  CHECK(csv.header.rfind("section,creature,engine,threads,", 0) == 0);
  std::map<std::string, int> rows_per_section;
  std::map<std::string, int> creature_engines;
  std::map<std::string, int> ga_engines; // engine -> creatures stepped
  for (const std::string& line : csv.rows) {
    const std::vector<std::string> f = csv_cells(line);
    REQUIRE(f.size() == 15);
    rows_per_section[f[0]]++;
    CHECK(std::stod(f[9]) > 0.0); // frames per second
    if (f[0] == "ga") {
      ga_engines[f[2]] = std::stoi(f[13]);
      if (f[2] == "seed") CHECK(f[11] == "1.00");
      if (f[2] == "plain") CHECK(f[12] == "1.00");
      CHECK((std::stod(f[14]) > 0.0) == (f[2] == "fast-replicas")); // replicas against fast-batch, in the same rounds
    }
    if (f[0] != "creature") continue;
    creature_engines[f[2]]++;
    if (f[2] == "seed") CHECK(f[11] == "1.00"); // a ratio to itself
    if (f[2] == "plain") CHECK(f[12] == "1.00");
    // The batched engines are measured against the baselines on the same batch:
    // so the batched seed is 1.00x "the seed" and the batched plain loop 1.00x
    // "plain" (against one creature they would differ by the machine's noise).
    if (f[2] == "seed-batch") CHECK(f[11] == "1.00");
    if (f[2] == "plain-batch") CHECK(f[12] == "1.00");
    if (f[2] == "seed" || f[2] == "plain") CHECK(f[13] == "1");
    if (f[2] == "seed-batch" || f[2] == "plain-batch") CHECK(f[13] == "16");
  }
  // The three bundled creatures under every engine, a size sweep, 1 and 2 threads twice.
  const std::map<std::string, int> three_each{{"fast", 3},      {"fast-batch", 3}, {"fast-batch-fused", 3},
                                              {"fast-batch-same", 3}, {"fast-no-wave", 3}, {"fast-sse2", 3},
                                              {"plain", 3},      {"plain-batch", 3}, {"reference", 3},
                                              {"seed", 3},       {"seed-batch", 3}};
  CHECK(creature_engines == three_each);
  // The bound on one creature alone, for each of the three (all have a wave).
  const std::string md_text = soda::read_whole_file(out / "speed.md");
  for (const char* name : {"- dainty_walker: ", "- carefulslug: ", "- monster_truck: "}) {
    const std::size_t at = md_text.find(name);
    REQUIRE(at != std::string::npos);
    CHECK(md_text.find("without the sines (fast-no-wave, ", at) < md_text.find('\n', at));
  }
  // The GA section: the first and the last saved generation of the run (--quick),
  // 24 creatures each, every engine on all of them.
  const std::map<std::string, int> ga_expected{{"fast", 48}, {"fast-batch", 48}, {"fast-replicas", 384}, {"plain", 48}, {"seed", 48}};
  CHECK(ga_engines == ga_expected);
  CHECK(md_text.find("The GA's own creatures, one core: the 48 creatures of 2 saved generations") != std::string::npos);
  CHECK(rows_per_section["size"] > 0);
  CHECK(rows_per_section["population"] == 4);
  const std::string md = soda::read_whole_file(out / "speed.md");
  CHECK(md.find("2-thread / 1-thread population throughput") != std::string::npos);
  CHECK(md.find("for chains of arithmetic bound by their own latency") != std::string::npos);
  CHECK(md.find("for items bound by the square-root/divide unit as the step is") != std::string::npos);
  // Every timed population run: the reported ratios are the medians over the rounds
  // of (1-thread time at the mean rate of the per-core runs) / (all-thread time).
  const CsvLines runs = read_csv_lines(out / "speed_rounds.csv");
  CHECK(runs.header == "round,work,threads,core,seconds,steal_ms");
  struct Round {
    std::vector<double> one_thread_rates;
    std::set<std::string> cores;
    double all_threads = 0.0;
  };
  std::map<std::string, std::map<int, Round>> by_work;
  for (const std::string& line : runs.rows) {
    const std::vector<std::string> f = csv_cells(line);
    REQUIRE(f.size() == 6);
    const double seconds = std::stod(f[4]);
    CHECK(seconds > 0.0);
    // Steal time in ms, or "-" where /proc/stat has none (then for every run).
    if (f[5] != "-") CHECK(std::stod(f[5]) >= 0.0);
    CHECK((f[5] == "-") == (md.find("steal time could not be read") != std::string::npos));
    if (f[1] != "fast" && f[1] != "fast-batch") continue;
    Round& round = by_work[f[1]][std::stoi(f[0])];
    if (f[2] == "1") {
      round.one_thread_rates.push_back(1.0 / seconds);
      round.cores.insert(f[3]);
    } else {
      CHECK(f[2] == "2");
      CHECK(f[3] == "-"); // the all-thread run is not held to a core
      round.all_threads = seconds;
    }
  }
  auto reported_after = [&](const std::string& lead) {
    const std::size_t at = md.find(lead);
    REQUIRE(at != std::string::npos);
    return std::stod(md.substr(at + lead.size()));
  };
  const double reported_fast = reported_after("population throughput: ");
  const double reported_batch = reported_after("x (fast), ");
  for (const auto& [work, rounds] : by_work) {
    INFO(work);
    REQUIRE(!rounds.empty());
    std::vector<double> ratios;
    for (const auto& [index, round] : rounds) {
      REQUIRE(round.all_threads > 0.0);
      // Held to each of the two cores in turn, or (where this process may not
      // choose its cores) one run not held.
      if (round.cores.count("-")) {
        CHECK(round.one_thread_rates.size() == 1);
      } else {
        CHECK(round.cores.size() == 2);
        CHECK(round.one_thread_rates.size() == 2);
      }
      double mean_rate = 0.0;
      for (double v : round.one_thread_rates) mean_rate += v / static_cast<double>(round.one_thread_rates.size());
      ratios.push_back((1.0 / mean_rate) / round.all_threads);
    }
    std::sort(ratios.begin(), ratios.end());
    const std::size_t n = ratios.size();
    const double median = n % 2 ? ratios[n / 2] : 0.5 * (ratios[n / 2 - 1] + ratios[n / 2]);
    // speed.md rounds to 2 decimals.
    CHECK((work == "fast" ? reported_fast : reported_batch) == Approx(median).margin(0.0051));
  }
  CHECK(by_work.size() == 2);
  CHECK(soda::read_whole_file(out / "speed.svg").find("<svg") != std::string::npos);
  CHECK(soda::read_whole_file(out / "speed_creatures.svg").find("<svg") != std::string::npos);
  fs::remove_all(out);
}

TEST_CASE("sodaevo with no arguments prints a short start-here whose commands work, --help still lists all", "[cli]") {
  const ShellResult r = run_sodaevo("");
  INFO(r.output);
  REQUIRE(r.exit_code == 0);
  CHECK_THAT(r.output, Catch::Contains("Start here"));
  // Short: a screenful, and none of the option list (that is --help).
  CHECK(std::count(r.output.begin(), r.output.end(), '\n') <= 24);
  CHECK(r.output.find("--resume") == std::string::npos);
  CHECK(r.output.find("SUBCOMMANDS") == std::string::npos);
  CHECK(r.output.find("Subcommands") == std::string::npos);
  CHECK_THAT(r.output, Catch::Contains("--help"));
  // The three commands, each runnable in the project folder as printed: the
  // files they name exist, and the simulate line runs.
  std::vector<std::string> commands;
  std::istringstream in(r.output);
  const std::string program = std::string(SODAEVO_BINARY) + " ";
  for (std::string line; std::getline(in, line);) {
    if (line.rfind("  " + program, 0) == 0) commands.push_back(line.substr(2 + program.size()));
  }
  REQUIRE(commands.size() == 3);
  CHECK(commands[0].rfind("evolve ", 0) == 0);
  CHECK(commands[1].rfind("designer ", 0) == 0);
  CHECK(commands[2].rfind("simulate ", 0) == 0);
  const fs::path project = fs::path(SODAEVO_MODELS_DIR).parent_path();
  for (const std::string& c : commands) {
    std::istringstream words(c);
    std::string command, file;
    words >> command >> file;
    INFO(c);
    CHECK(fs::exists(project / file));
  }
  const ShellResult simulated = run_shell("cd " + project.string() + " && " + program + commands[2]);
  INFO(simulated.output);
  CHECK(simulated.exit_code == 0);
  CHECK_THAT(simulated.output, Catch::Contains("px"));

  const ShellResult help = run_sodaevo("--help");
  INFO(help.output);
  REQUIRE(help.exit_code == 0);
  for (const char* command : {"simulate", "convert", "evolve", "export", "replay", "bench", "render", "report",
                              "designer", "race"}) {
    CHECK(help.output.find(command) != std::string::npos);
  }
}
