// The MPI evaluator as users run it: mpirun around the built binary, compared
// byte for byte with a single-process run; a rank killed or an evaluation failing
// mid-run leaves a run folder that resumes to the same result on another N.
//
// Skipped (with a message) only when mpirun is not on PATH or the build has no
// MPI; `./build.sh test` installs Open MPI, so CI runs them. Every mpirun runs
// under `timeout`, so a hung job cannot block the suite.
#include <catch2/catch.hpp>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <string>

#include "evolve/store/run_reader.hpp"
#include "evolve/store/run_store.hpp"
#include "formats/atomic_file.hpp"
#include "test_support.hpp"

namespace fs = std::filesystem;

namespace {

using sodaevo::test::run_shell;
using sodaevo::test::run_sodaevo;
using sodaevo::test::sodaevo_command;
using Ran = sodaevo::test::ShellResult;

bool mpirun_available() { return run_shell("command -v mpirun").exit_code == 0; }

/// Why the MPI tests cannot run here, or empty.
std::string why_skip() {
  if (SODAEVO_HAS_MPI == 0) return "this build has no MPI (SODAEVO_MPI off or no MPI library)";
  if (!mpirun_available()) return "mpirun not found (install openmpi-bin; ./build.sh test does)";
  return {};
}

std::string mpirun(int ranks, const std::string& args, const std::string& env = "") {
  return env + " timeout -k 10 180 mpirun --allow-run-as-root --oversubscribe -np " + std::to_string(ranks) + " " +
         sodaevo_command(args);
}

fs::path mpi_work_dir(const std::string& name) { return sodaevo::test::fresh_temp_dir("mpi_" + name); }

fs::path write_config(const fs::path& dir, int generations) {
  const fs::path config = dir / "mpi_test.json";
  std::ofstream(config) << R"({ "name": "mpitest", "seed": 42, "generations": )" << generations << R"(,
  "population": { "size": 12, "seed_models": [")"
                        << fs::absolute(sodaevo::test::models_dir() / "dainty_walker.xml").string() << R"("],
                  "random_fraction": 0.5 },
  "crossover": { "rate": 0.3 },
  "fitness": { "frames": 400, "settle_frames": 50 },
  "save": { "generation_every": 2, "checkpoint_every": 1 } })";
  return config;
}

std::string mpi_file_text(const fs::path& p) { return soda::read_whole_file(p); }

/// Everything but timing.csv, manifest.json and checkpoint.json (wall times).
void require_same_run_folder(const fs::path& a, const fs::path& b) {
  CHECK(mpi_file_text(a / "config.json") == mpi_file_text(b / "config.json"));
  CHECK(mpi_file_text(a / "generations.csv") == mpi_file_text(b / "generations.csv"));
  const std::vector<int> saved = sodaevo::saved_generations(a);
  REQUIRE(!saved.empty());
  CHECK(saved == sodaevo::saved_generations(b));
  for (const auto& entry : fs::directory_iterator(a / "best")) {
    INFO(entry.path().filename());
    CHECK(mpi_file_text(entry.path()) == mpi_file_text(b / "best" / entry.path().filename()));
  }
  for (int g : saved) {
    INFO("generation " << g);
    CHECK(mpi_file_text(a / "generations" / sodaevo::generation_file_name(g)) ==
          mpi_file_text(b / "generations" / sodaevo::generation_file_name(g)));
  }
  CHECK(std::distance(fs::directory_iterator(a / "best"), fs::directory_iterator()) ==
        std::distance(fs::directory_iterator(b / "best"), fs::directory_iterator()));
}

} // namespace

TEST_CASE("mpirun -np 3 (and -np 2 with 2 threads each) writes the same run folder as one process", "[mpi]") {
  if (const std::string why = why_skip(); !why.empty()) {
    WARN("skipped: " << why);
    return;
  }
  const fs::path dir = mpi_work_dir("identical");
  const fs::path config = write_config(dir, 6);
  const Ran one = run_sodaevo("evolve " + config.string() + " --out " + (dir / "one").string() + " --threads 2 --quiet");
  INFO(one.output);
  REQUIRE(one.exit_code == 0);
  const Ran three = run_shell(mpirun(3, "evolve " + config.string() + " --out " + (dir / "three").string() + " --threads 1"));
  INFO(three.output);
  REQUIRE(three.exit_code == 0);
  // The work really was shared: other ranks evaluated creatures.
  CHECK(three.output.find("MPI: ") != std::string::npos);
  CHECK(three.output.find(" 0 on other ranks") == std::string::npos);
  require_same_run_folder(dir / "one", dir / "three");
  // Several threads per rank (workers evaluate their chunks in parallel too).
  const Ran two = run_shell(mpirun(2, "evolve " + config.string() + " --out " + (dir / "two").string() + " --threads 2 --quiet"));
  INFO(two.output);
  REQUIRE(two.exit_code == 0);
  require_same_run_folder(dir / "one", dir / "two");
  fs::remove_all(dir);
}

TEST_CASE("a rank killed mid-run leaves a run folder that resumes on another N", "[mpi]") {
  if (const std::string why = why_skip(); !why.empty()) {
    WARN("skipped: " << why);
    return;
  }
  const fs::path dir = mpi_work_dir("killed");
  const fs::path config = write_config(dir, 8);
  REQUIRE(run_sodaevo("evolve " + config.string() + " --out " + (dir / "ref").string() + " --quiet").exit_code == 0);

  // Rank 2 kills itself (SIGKILL) as it starts its 3rd chunk, in generation 2 at the latest.
  const Ran killed = run_shell(mpirun(3, "evolve " + config.string() + " --out " + (dir / "run").string() + " --threads 1",
                                      "SODAEVO_TEST_FAULT=kill:2:2"));
  INFO(killed.output);
  CHECK(killed.exit_code != 0);
  // Not checked here: rank 0's "continue with: sodaevo evolve --resume" on mpirun's
  // SIGTERM. mpirun sends SIGKILL one second later (odls_base_sigkill_timeout), a
  // time a loaded machine may not give rank 0, and then the message is lost: this
  // test failed now and then for that alone. test_crash_safety.cpp checks the
  // message on a SIGTERM that nothing follows. Everything below waits on events.
  // Intact: the run folder opens, and its checkpoint, if the kill came after the
  // first one (rank 2 may take several chunks of generation 0 when the other
  // ranks are slow), is readable and of a generation before the end.
  sodaevo::RunStore store = sodaevo::RunStore::open(dir / "run");
  const auto checkpoint = store.read_checkpoint();
  if (checkpoint) CHECK(checkpoint->generation.index <= 1);
  const std::string log = mpi_file_text(dir / "run" / "generations.csv");
  CHECK(std::count(log.begin(), log.end(), '\n') <= 1 + 2); // header and at most generations 0 and 1

  const Ran resumed = run_shell(mpirun(2, "evolve --resume " + (dir / "run").string() + " --threads 1 --quiet"));
  INFO(resumed.output);
  REQUIRE(resumed.exit_code == 0);
  require_same_run_folder(dir / "ref", dir / "run");
  fs::remove_all(dir);
}

TEST_CASE("a failed evaluation on a worker stops the run with a message, it resumes in one process", "[mpi]") {
  if (const std::string why = why_skip(); !why.empty()) {
    WARN("skipped: " << why);
    return;
  }
  const fs::path dir = mpi_work_dir("failed");
  const fs::path config = write_config(dir, 6);
  REQUIRE(run_sodaevo("evolve " + config.string() + " --out " + (dir / "ref").string() + " --quiet").exit_code == 0);
  const Ran failed = run_shell(mpirun(3, "evolve " + config.string() + " --out " + (dir / "run").string() + " --threads 1 --quiet",
                                      "SODAEVO_TEST_FAULT=fail:1:2"));
  INFO(failed.output);
  CHECK(failed.exit_code != 0);
  CHECK(failed.output.find("sodaevo: error: MPI rank 1 on ") != std::string::npos);
  CHECK(failed.output.find("test fault injected") != std::string::npos);
  CHECK(failed.output.find("sodaevo evolve --resume " + (dir / "run").string()) != std::string::npos);
  // Stopped politely (workers told to stop), not by MPI_Abort.
  CHECK(failed.output.find("MPI_ABORT") == std::string::npos);

  const Ran resumed = run_sodaevo("evolve --resume " + (dir / "run").string() + " --quiet");
  INFO(resumed.output);
  REQUIRE(resumed.exit_code == 0);
  require_same_run_folder(dir / "ref", dir / "run");
  fs::remove_all(dir);
}

TEST_CASE("MAP-Elites over mpirun -np 3 writes the archive of one process", "[mpi][map-elites]") {
  if (const std::string why = why_skip(); !why.empty()) {
    WARN("skipped: " << why);
    return;
  }
  const fs::path dir = mpi_work_dir("map_elites");
  const fs::path config = dir / "me.json";
  std::ofstream(config) << R"({ "name": "mpime", "seed": 5, "algorithm": "map-elites",
  "population": { "size": 12, "seed_models": [")"
                        << fs::absolute(sodaevo::test::models_dir() / "dainty_walker.xml").string() << R"("],
                  "random_fraction": 0.5 },
  "fitness": { "frames": 300, "settle_frames": 40, "replicas": 2, "replicas_max": 4 },
  "map_elites": { "descriptors": ["width", "mass_count"], "bins": [6, 6], "ranges": [[0, 240], [2.5, 14.5]],
                  "iterations": 3, "batch_size": 10, "snapshot_every": 0 },
  "save": { "checkpoint_every": 1 } })";
  const Ran one = run_sodaevo("evolve " + config.string() + " --out " + (dir / "one").string() + " --threads 2 --quiet");
  INFO(one.output);
  REQUIRE(one.exit_code == 0);
  const Ran three = run_shell(mpirun(3, "evolve " + config.string() + " --out " + (dir / "three").string() + " --threads 1 --quiet"));
  INFO(three.output);
  REQUIRE(three.exit_code == 0);
  CHECK(mpi_file_text(dir / "one" / "qd.csv") == mpi_file_text(dir / "three" / "qd.csv"));
  CHECK(mpi_file_text(dir / "one" / "archive.json") == mpi_file_text(dir / "three" / "archive.json"));
  int elites = 0;
  for (const auto& entry : fs::directory_iterator(dir / "one" / "elites")) {
    INFO(entry.path().filename());
    CHECK(mpi_file_text(entry.path()) == mpi_file_text(dir / "three" / "elites" / entry.path().filename()));
    ++elites;
  }
  CHECK(elites > 0);
  fs::remove_all(dir);
}

TEST_CASE("the CLI says whether MPI is built in", "[mpi]") {
  const Ran version = run_sodaevo("--version");
  REQUIRE(version.exit_code == 0);
  CHECK(version.output.find(SODAEVO_HAS_MPI ? "MPI: yes" : "MPI: no") != std::string::npos);
  if (SODAEVO_HAS_MPI == 0) {
    // Started as if by mpirun with 3 ranks: refused with a clear message, nothing written.
    const fs::path dir = mpi_work_dir("no_mpi");
    const fs::path config = write_config(dir, 2);
    const Ran r = run_shell("OMPI_COMM_WORLD_SIZE=3 " + sodaevo_command("evolve " + config.string() + " --out " + (dir / "run").string()));
    INFO(r.output);
    CHECK(r.exit_code != 0);
    CHECK(r.output.find("built without MPI support") != std::string::npos);
    CHECK(!fs::exists(dir / "run"));
    fs::remove_all(dir);
  }
}
