// A run folder records which muscle sine made it, and replay, report and
// evolve --resume of a folder made with another sine say so instead of reporting
// a fitness mismatch or silently mixing two sines in one run.
//
// An "old" folder is made from a fresh run by taking the sine out of its manifest
// and checkpoint (as folders made before sines were recorded are) and changing
// one logged fitness (as another sine would): a check blind to the sine then
// reports a mismatch or resumes, and these tests go red.
#include <catch2/catch.hpp>

#include <filesystem>
#include <string>

#include <nlohmann/json.hpp>

#include "core/sine_identity.hpp"
#include "evolve/config/map_elites_config.hpp"
#include "evolve/store/run_sine.hpp"
#include "formats/atomic_file.hpp"
#include "test_support.hpp"

using namespace sodaevo;
using namespace sodaevo::test;
namespace fs = std::filesystem;
using nlohmann::json;

namespace {

const std::string kEngine(soda::kEngineSine);
const std::string kGlibc(soda::kGlibcSine);

json read_json(const fs::path& p) { return json::parse(soda::read_whole_file(p)); }
void write_json(const fs::path& p, const json& j) { soda::write_file_atomically(p, j.dump(2) + "\n"); }

/// A finished 3-generation GA run (every generation saved whole) in `dir`.
void make_run(const fs::path& dir, const fs::path& work) {
  RunConfig c = walker_run_config("sine", 7, 6, 3, 200, 20);
  c.save.generation_every = 1;
  write_json(work / "sine.json", to_json(c));
  const ShellResult r = run_sodaevo("evolve " + (work / "sine.json").string() + " --quiet --threads 1 --out " + dir.string());
  INFO(r.output);
  REQUIRE(r.exit_code == 0);
}

/// Replaces the first fitness="..." of a saved generation with another number.
void change_first_fitness(const fs::path& generation_file) {
  std::string text = soda::read_whole_file(generation_file);
  const std::size_t at = text.find("fitness=\"");
  REQUIRE(at != std::string::npos);
  const std::size_t end = text.find('"', at + 9);
  text.replace(at + 9, end - at - 9, "12345.5");
  soda::write_file_atomically(generation_file, text);
}

/// `dir` as made before the engine recorded its sine: no "sine" in manifest.json
/// or checkpoint.json; generation 2's first logged fitness changed.
void make_old(const fs::path& dir) {
  json manifest = read_json(dir / "manifest.json");
  REQUIRE(manifest.erase("sine") == 1);
  write_json(dir / "manifest.json", manifest);
  json checkpoint = read_json(dir / "checkpoint.json");
  REQUIRE(checkpoint.erase("sine") == 1);
  soda::write_file_atomically(dir / "checkpoint.json", checkpoint.dump() + "\n");
  change_first_fitness(dir / "generations" / "gen_00002.xml");
}

bool has(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

} // namespace

TEST_CASE("a run folder records the engine's sine in its manifest and checkpoint", "[cli][run-sine]") {
  const fs::path work = fresh_temp_dir("sine_records");
  make_run(work / "run", work);
  CHECK(read_json(work / "run" / "manifest.json").at("sine") == kEngine);
  CHECK(read_json(work / "run" / "checkpoint.json").at("sine") == kEngine);
  const ShellResult replay = run_sodaevo("replay " + (work / "run").string() + " --threads 1");
  INFO(replay.output);
  CHECK(replay.exit_code == 0);
  CHECK(has(replay.output, "6 reproduce the logged fitness exactly, 0 differ"));
  CHECK(!has(replay.output, "note:"));
  // A changed fitness in a run of this engine is a mismatch (what the old run's must not be).
  change_first_fitness(work / "run" / "generations" / "gen_00002.xml");
  const ShellResult changed = run_sodaevo("replay " + (work / "run").string() + " --threads 1");
  CHECK(changed.exit_code == 3);
  CHECK(has(changed.output, "MISMATCH"));
  fs::remove_all(work);
}

TEST_CASE("replay and report of a run made before sines were recorded say so and report no mismatch",
          "[cli][run-sine]") {
  const fs::path work = fresh_temp_dir("sine_old_replay");
  const fs::path old = work / "old";
  make_run(old, work);
  make_old(old);
  const ShellResult replay = run_sodaevo("replay " + old.string() + " --threads 1");
  INFO(replay.output);
  CHECK(replay.exit_code == 0);
  CHECK(has(replay.output, "note: generation 2 of this run was made with glibc's sin (glibc-x86_64-fma: its "
                           "manifest.json names no sine, as runs made before 2026-11-27 do not); this engine "
                           "computes Java's Math.sin (java-hotspot-x86_64)"));
  CHECK(has(replay.output, "re-simulated fitnesses will differ from the logged ones"));
  CHECK(!has(replay.output, "MISMATCH"));
  CHECK(has(replay.output, "generation 2: 6 creatures re-simulated with this engine's sine"));

  const ShellResult report = run_sodaevo("report " + old.string());
  INFO(report.output);
  CHECK(report.exit_code == 0);
  CHECK(has(report.output, "note: this run was made with glibc's sin"));
  const std::string page = soda::read_whole_file(old / "report.html");
  CHECK(has(page, "<p class=\"sine-note\">Made with another sine: this run was made with glibc&apos;s sin"));
  CHECK(has(page, "not recorded: runs before 2026-11-27 record no sine"));
  fs::remove_all(work);
}

TEST_CASE("a manifest naming a sine this sodaevo does not know says so", "[cli][run-sine]") {
  const fs::path work = fresh_temp_dir("sine_unknown");
  const fs::path run = work / "run";
  make_run(run, work);
  json manifest = read_json(run / "manifest.json");
  manifest["sine"] = "fdlibm-strictmath";
  write_json(run / "manifest.json", manifest);
  const ShellResult replay = run_sodaevo("replay " + run.string() + " --threads 1");
  INFO(replay.output);
  CHECK(replay.exit_code == 0);
  CHECK(has(replay.output, "was made with a sine this sodaevo does not know ('fdlibm-strictmath')"));
  CHECK(has(replay.output, "will differ unless the two sines agree in every bit"));
  // The checkpoint says this engine, the manifest not: resume believes neither alone.
  const ShellResult resume = run_sodaevo("evolve --resume " + run.string() + " --quiet --threads 1");
  CHECK(resume.exit_code != 0);
  CHECK(has(resume.output, "not resumed"));
  CHECK(has(resume.output, "manifest.json"));
  fs::remove_all(work);
}

TEST_CASE("resume of a run made with another sine refuses, and --resume-other-sine continues and records it",
          "[cli][run-sine]") {
  const fs::path work = fresh_temp_dir("sine_resume");
  const fs::path old = work / "old";
  make_run(old, work);
  make_old(old);
  // One generation more than the run made, so that a resume has one to make.
  json config = read_json(old / "config.json");
  config["generations"] = 4;
  write_json(old / "config.json", config);
  const std::string checkpoint_before = soda::read_whole_file(old / "checkpoint.json");

  const ShellResult refused = run_sodaevo("evolve --resume " + old.string() + " --quiet --threads 1");
  INFO(refused.output);
  CHECK(refused.exit_code != 0);
  CHECK(has(refused.output, "not resumed: this run was made with glibc's sin"));
  CHECK(has(refused.output, "Continuing it here would mix two sines in one run"));
  CHECK(has(refused.output, "sodaevo evolve --resume " + old.string() + " --resume-other-sine"));
  CHECK(soda::read_whole_file(old / "checkpoint.json") == checkpoint_before);
  CHECK(!fs::exists(old / "generations" / "gen_00003.xml"));
  CHECK(!read_json(old / "manifest.json").contains("sine"));

  const ShellResult resumed = run_sodaevo("evolve --resume " + old.string() + " --resume-other-sine --quiet --threads 1");
  INFO(resumed.output);
  REQUIRE(resumed.exit_code == 0);
  CHECK(has(resumed.output, "Continuing with this engine's sine (--resume-other-sine): generation 2 is scored again"));
  const json manifest = read_json(old / "manifest.json");
  CHECK(manifest.at("sine") == kEngine);
  REQUIRE(manifest.at("sine_changes").size() == 1);
  CHECK(manifest["sine_changes"][0]["generation"] == 2);
  CHECK(manifest["sine_changes"][0]["from"] == kGlibc);
  CHECK(manifest["sine_changes"][0]["to"] == kEngine);
  CHECK(read_json(old / "checkpoint.json").at("sine") == kEngine);
  REQUIRE(fs::exists(old / "generations" / "gen_00003.xml"));

  // Generations 2 (scored again) and 3 are this engine's: they reproduce exactly.
  for (const char* g : {"2", "3"}) {
    const ShellResult replay = run_sodaevo("replay " + old.string() + " -g " + g + " --threads 1");
    INFO(replay.output);
    CHECK(replay.exit_code == 0);
    CHECK(has(replay.output, "reproduce the logged fitness exactly, 0 differ"));
  }
  // Generation 1 is still glibc's, now recorded as such.
  const ShellResult replay1 = run_sodaevo("replay " + old.string() + " -g 1 --threads 1");
  INFO(replay1.output);
  CHECK(has(replay1.output, "note: generation 1 of this run was made with glibc's sin (glibc-x86_64-fma, the engine "
                            "before 2026-11-27)"));
  const ShellResult report = run_sodaevo("report " + old.string());
  CHECK(has(report.output, "note: generations 0-1 of this run were made with glibc's sin"));
  CHECK(has(soda::read_whole_file(old / "report.html"),
            "glibc&apos;s sin (glibc-x86_64-fma, the engine before 2026-11-27) for generations 0-1, then Java&apos;s "
            "Math.sin (java-hotspot-x86_64) from generation 2"));
  // A plain resume now goes on (nothing left to mix).
  config["generations"] = 5;
  write_json(old / "config.json", config);
  const ShellResult again = run_sodaevo("evolve --resume " + old.string() + " --quiet --threads 1");
  INFO(again.output);
  CHECK(again.exit_code == 0);
  CHECK(fs::exists(old / "generations" / "gen_00004.xml"));
  fs::remove_all(work);
}

TEST_CASE("a MAP-Elites run made with another sine is not resumed, flag or not", "[cli][run-sine]") {
  const fs::path work = fresh_temp_dir("sine_map_elites");
  RunConfig c = walker_run_config("me", 7, 8, 1, 200, 20);
  c.algorithm = AlgorithmKind::MapElites;
  c.map_elites.axes = {{Descriptor::Width, 4, 0.0, 240.0}, {Descriptor::MassCount, 4, 2.5, 14.5}};
  c.map_elites.iterations = 2;
  c.map_elites.batch_size = 8;
  write_json(work / "me.json", to_json(c));
  const fs::path run = work / "me";
  const ShellResult made = run_sodaevo("evolve " + (work / "me.json").string() + " --quiet --threads 1 --out " + run.string());
  INFO(made.output);
  REQUIRE(made.exit_code == 0);
  CHECK(read_json(run / "archive_checkpoint.json").at("sine") == kEngine);
  CHECK(read_json(run / "archive.json").at("sine") == kEngine);
  json checkpoint = read_json(run / "archive_checkpoint.json");
  checkpoint.erase("sine");
  soda::write_file_atomically(run / "archive_checkpoint.json", checkpoint.dump() + "\n");
  for (const char* flag : {"", " --resume-other-sine"}) {
    const ShellResult r = run_sodaevo("evolve --resume " + run.string() + flag + " --quiet --threads 1");
    INFO(r.output);
    CHECK(r.exit_code != 0);
    CHECK(has(r.output, "not resumed: this run was made with glibc's sin"));
    CHECK(has(r.output, "A MAP-Elites archive cannot change sine part way"));
  }
  fs::remove_all(work);
}

TEST_CASE("run_sine: the sine of each generation, and a malformed record named with its file", "[run-sine]") {
  const fs::path work = fresh_temp_dir("sine_unit");
  RunSine run = read_run_sine(work); // no manifest: nothing recorded, glibc's by the rule
  CHECK(!run.recorded);
  CHECK(run.sine == kGlibc);
  CHECK(!run.all_engine());

  write_json(work / "manifest.json", {{"sine", kEngine},
                                      {"sine_changes", json::array({{{"generation", 5}, {"from", kGlibc}, {"to", kEngine}}})}});
  run = read_run_sine(work);
  CHECK(run.of_generation(0) == kGlibc);
  CHECK(run.of_generation(4) == kGlibc);
  CHECK(run.of_generation(5) == kEngine);
  CHECK(run.of_generation(9) == kEngine);
  CHECK(!run.all_engine());
  CHECK(has(run_sine_note(run), "generations 0-4 of this run were made with glibc's sin"));

  write_json(work / "manifest.json", {{"sine", kEngine}});
  CHECK(read_run_sine(work).all_engine());
  CHECK(run_sine_note(read_run_sine(work)).empty());

  write_json(work / "manifest.json", {{"sine", 5}});
  CHECK_THROWS_WITH(read_run_sine(work), (work / "manifest.json").string() +
                                             ": /sine: expected a sine's name (e.g. \"java-hotspot-x86_64\"), got 5");
  write_json(work / "manifest.json",
             {{"sine", kGlibc}, {"sine_changes", json::array({{{"generation", 2}, {"from", kGlibc}, {"to", kEngine}}})}});
  CHECK_THROWS_WITH(read_run_sine(work), Catch::Contains("/sine: expected the last change's \"to\""));
  fs::remove_all(work);
}
