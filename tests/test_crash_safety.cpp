// Crash safety of runs, tested on the real binary: `sodaevo evolve` killed with
// SIGKILL at random moments, several times, must leave a run folder whose every
// file is complete and parseable, and `--resume` must then finish the run with
// results byte-identical to a run that was never interrupted. A folder that
// cannot be written (or a disk that fills) gives a clear error and loses nothing.
#include <catch2/catch.hpp>

#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <map>
#include <random>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include <nlohmann/json.hpp>

#include "evolve/config/run_config.hpp"
#include "evolve/store/run_store.hpp"
#include "formats/atomic_file.hpp"
#include "formats/model_file.hpp"
#include "test_support.hpp"

extern char** environ;

using namespace sodaevo;
namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

namespace {

fs::path work_dir(const std::string& name) { return test::fresh_temp_dir("crash_" + name); }

/// Starts a program with stdout and stderr going to `log`; returns its pid.
pid_t spawn(const std::vector<std::string>& args, const fs::path& log) {
  std::vector<char*> argv;
  for (const std::string& a : args) argv.push_back(const_cast<char*>(a.c_str()));
  argv.push_back(nullptr);
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, STDIN_FILENO, "/dev/null", O_RDONLY, 0);
  posix_spawn_file_actions_addopen(&actions, STDOUT_FILENO, log.c_str(), O_WRONLY | O_CREAT | O_APPEND, 0644);
  posix_spawn_file_actions_adddup2(&actions, STDOUT_FILENO, STDERR_FILENO);
  pid_t pid = -1;
  const int rc = posix_spawn(&pid, argv[0], &actions, nullptr, argv.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  REQUIRE(rc == 0);
  return pid;
}

/// Exit code of a finished child (128 + signal if it was killed).
int wait_for(pid_t pid) {
  int status = 0;
  REQUIRE(::waitpid(pid, &status, 0) == pid);
  return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
}

/// Runs a program to its end; returns the exit code.
int run(const std::vector<std::string>& args, const fs::path& log) { return wait_for(spawn(args, log)); }

std::string text_of(const fs::path& p) { return soda::read_whole_file(p); }

std::vector<std::string> evolve_args(const std::vector<std::string>& more) {
  std::vector<std::string> args = {SODAEVO_BINARY, "evolve"};
  args.insert(args.end(), more.begin(), more.end());
  args.insert(args.end(), {"--threads", "2", "--quiet"});
  return args;
}

/// A config that takes a couple of seconds: enough generations for kills to land
/// between checkpoints (every 2nd generation) and saves (every generation).
fs::path write_config(const fs::path& dir) {
  const nlohmann::json config = {
      {"name", "crash"},
      {"seed", 7},
      {"generations", 24},
      {"population",
       {{"size", 12},
        {"seed_models", {fs::absolute(sodaevo::test::models_dir() / "dainty_walker.xml").string()}},
        {"random_fraction", 0.5}}},
      {"crossover", {{"rate", 0.3}}},
      {"fitness", {{"frames", 400}, {"settle_frames", 40}}},
      {"save", {{"generation_every", 1}, {"checkpoint_every", 2}}}};
  const fs::path path = dir / "crash.json";
  std::ofstream(path) << config.dump(2);
  return path;
}

bool is_temporary(const fs::path& p) { return p.filename().string().find(".tmp-") != std::string::npos; }

/// Every file of a run folder, relative path -> content (temporary files left by a
/// killed write excluded; they are counted in `temporaries`).
std::map<std::string, std::string> folder_files(const fs::path& run, int* temporaries = nullptr) {
  std::map<std::string, std::string> files;
  for (const fs::directory_entry& e : fs::recursive_directory_iterator(run)) {
    if (!e.is_regular_file()) continue;
    if (is_temporary(e.path())) {
      if (temporaries) ++*temporaries;
      continue;
    }
    files[fs::relative(e.path(), run).string()] = text_of(e.path());
  }
  return files;
}

/// Checks that each file of the run folder is complete: it parses with the reader
/// the program itself uses, and a CSV has whole rows of the right width.
void require_complete_files(const fs::path& run) {
  for (const auto& [name, text] : folder_files(run)) {
    INFO("run file " << name);
    const fs::path path = run / name;
    if (name == "config.json") {
      CHECK_NOTHROW(read_run_config(path));
    } else if (name == "manifest.json" || name == "champions.json") {
      CHECK_NOTHROW(nlohmann::json::parse(text));
    } else if (name == "checkpoint.json") {
      CHECK_NOTHROW(parse_checkpoint(text, path.string()));
    } else if (name == "generations.csv" || name == "timing.csv") {
      const long columns = name == "generations.csv" ? 13 : 4;
      REQUIRE(!text.empty());
      CHECK(text.back() == '\n');
      std::istringstream in(text);
      std::string line;
      while (std::getline(in, line)) CHECK(std::count(line.begin(), line.end(), ',') + 1 == columns);
    } else if (name == "report.html" || name == "designer.html") { // the designer the report links to
      CHECK(text.find("</html>") != std::string::npos);
    } else if (name.rfind("best/", 0) == 0 || name.rfind("seeds/", 0) == 0) {
      CHECK_NOTHROW(soda::read_model_file(path));
    } else if (name.rfind("generations/", 0) == 0) {
      CHECK_NOTHROW(generation_from_xml(text, path.string()));
    } else {
      FAIL("unexpected file in the run folder");
    }
  }
}

/// The results that must not depend on interruptions: everything but timing.csv,
/// manifest.json (start time, command line), report.html (shows timing) and the
/// checkpoint's wall time.
std::map<std::string, std::string> results_of(const fs::path& run) {
  std::map<std::string, std::string> files = folder_files(run);
  files.erase("timing.csv");
  files.erase("manifest.json");
  files.erase("report.html");
  const Checkpoint c = parse_checkpoint(files.at("checkpoint.json"), "checkpoint.json");
  files["checkpoint.json"] =
      std::to_string(c.evaluations) + "\n" + generation_to_xml(c.generation); // without wall_seconds
  return files;
}

void require_same_results(const fs::path& expected_run, const fs::path& run) {
  const auto expected = results_of(expected_run);
  const auto got = results_of(run);
  std::vector<std::string> expected_names, got_names;
  for (const auto& [name, text] : expected) expected_names.push_back(name);
  for (const auto& [name, text] : got) got_names.push_back(name);
  REQUIRE(got_names == expected_names);
  for (const auto& [name, text] : expected) {
    INFO("result file " << name);
    CHECK(got.at(name) == text);
  }
}

} // namespace

TEST_CASE("a run killed with SIGKILL at random moments resumes to the uninterrupted result", "[crash]") {
  const fs::path dir = work_dir("kill");
  const fs::path config = write_config(dir);
  const fs::path log = dir / "log.txt";

  const auto t0 = Clock::now();
  REQUIRE(run(evolve_args({config.string(), "--out", (dir / "whole").string()}), log) == 0);
  const double whole_seconds = std::chrono::duration<double>(Clock::now() - t0).count();
  require_complete_files(dir / "whole");

  const unsigned seed = std::random_device{}();
  INFO("kill moments drawn with seed " << seed << "; the uninterrupted run took " << whole_seconds << " s");
  std::mt19937 rng(seed);
  // A kill moment is drawn in progress, not in wall time (the machine's load may
  // change between the runs): once the run has logged a random number of further
  // generations (0 to 4), wait a random part of one generation's time and kill.
  // At most 4 of the 24 generations per attempt, so four kills land before the end.
  const double generation_seconds = whole_seconds / 24.0;
  std::uniform_int_distribution<long> more_generations(0, 4);
  std::uniform_real_distribution<double> within_generation(0.0, generation_seconds);
  const fs::path killed = dir / "killed";
  auto logged_generations = [&] {
    std::error_code ec;
    if (!fs::exists(killed / "generations.csv", ec)) return 0L;
    const std::string text = text_of(killed / "generations.csv");
    return std::max(0L, static_cast<long>(std::count(text.begin(), text.end(), '\n')) - 1);
  };
  int kills = 0;
  bool finished = false;
  for (int attempt = 0; attempt < 8 && kills < 4 && !finished; ++attempt) {
    const long target = std::min(20L, logged_generations() + more_generations(rng));
    const pid_t pid =
        spawn(attempt == 0 ? evolve_args({config.string(), "--out", killed.string()})
                           : evolve_args({"--resume", killed.string()}),
              log);
    int status = 0;
    pid_t done = 0;
    auto running = [&] { return done == 0 && (done = ::waitpid(pid, &status, WNOHANG)) == 0; };
    // Resuming needs the run folder's config: kill only once it is there.
    while (running() && !fs::exists(killed / "config.json")) std::this_thread::sleep_for(std::chrono::microseconds(500));
    while (running() && logged_generations() < target) std::this_thread::sleep_for(std::chrono::microseconds(500));
    const auto deadline = Clock::now() + std::chrono::duration<double>(within_generation(rng));
    while (running() && Clock::now() < deadline) std::this_thread::sleep_for(std::chrono::microseconds(500));
    if (done == 0) {
      ::kill(pid, SIGKILL);
      const int code = wait_for(pid);
      if (code == 128 + SIGKILL) ++kills;
      else finished = code == 0;
    } else {
      REQUIRE(WIFEXITED(status));
      REQUIRE(WEXITSTATUS(status) == 0);
      finished = true;
    }
    INFO("after attempt " << attempt);
    require_complete_files(killed);
  }
  CHECK(kills >= 3);
  // Finish the run (again, if it finished already: a finished run resumes to itself).
  REQUIRE(run(evolve_args({"--resume", killed.string()}), log) == 0);
  int temporaries = 0;
  folder_files(killed, &temporaries);
  CHECK(temporaries == 0);
  require_complete_files(killed);
  require_same_results(dir / "whole", killed);
  fs::remove_all(dir.parent_path());
}

TEST_CASE("Ctrl-C finishes the generation, writes everything, exits 0, and the run resumes", "[crash]") {
  const fs::path dir = work_dir("interrupt");
  const fs::path config = write_config(dir);
  const fs::path log = dir / "log.txt";
  REQUIRE(run(evolve_args({config.string(), "--out", (dir / "whole").string()}), log) == 0);

  const fs::path stopped = dir / "stopped";
  const pid_t pid = spawn(evolve_args({config.string(), "--out", stopped.string()}), log);
  auto rows = [&] {
    std::error_code ec;
    if (!fs::exists(stopped / "generations.csv", ec)) return 0L;
    const std::string text = text_of(stopped / "generations.csv");
    return static_cast<long>(std::count(text.begin(), text.end(), '\n')) - 1;
  };
  const auto give_up = Clock::now() + std::chrono::seconds(120);
  while (rows() < 2 && Clock::now() < give_up) std::this_thread::sleep_for(std::chrono::milliseconds(1));
  ::kill(pid, SIGINT);
  CHECK(wait_for(pid) == 0);
  require_complete_files(stopped);
  const long done = rows();
  CHECK(done < 24); // it stopped early...
  // ...and saved the generation it finished: the checkpoint is the last logged one.
  const Checkpoint c = parse_checkpoint(text_of(stopped / "checkpoint.json"), "checkpoint.json");
  CHECK(c.generation.index == done - 1);
  REQUIRE(run(evolve_args({"--resume", stopped.string()}), log) == 0);
  require_same_results(dir / "whole", stopped);
  fs::remove_all(dir.parent_path());
}

TEST_CASE("SIGTERM (mpirun's stop when a rank dies) says how to resume, the run resumes", "[crash][mpi]") {
  // The message that test_mpi.cpp's killed rank cannot check reliably: under
  // mpirun, rank 0 has one second (Open MPI's odls_base_sigkill_timeout) between
  // SIGTERM and SIGKILL, which a loaded machine may not give it. Here nothing
  // follows the SIGTERM, and the test waits on events only: a checkpoint on disk,
  // then the process's end.
  const fs::path dir = work_dir("sigterm");
  const fs::path config = write_config(dir);
  const fs::path log = dir / "log.txt";
  REQUIRE(run(evolve_args({config.string(), "--out", (dir / "whole").string()}), log) == 0);

  const fs::path stopped = dir / "stopped";
  const fs::path stopped_log = dir / "stopped_log.txt";
  const pid_t pid = spawn(evolve_args({config.string(), "--out", stopped.string()}), stopped_log);
  int status = 0;
  pid_t done = 0;
  auto running = [&] { return done == 0 && (done = ::waitpid(pid, &status, WNOHANG)) == 0; };
  while (running() && !fs::exists(stopped / "checkpoint.json")) std::this_thread::sleep_for(std::chrono::microseconds(500));
  REQUIRE(done == 0); // the run (24 generations) is still going at its first checkpoint
  ::kill(pid, SIGTERM);
  REQUIRE(::waitpid(pid, &status, 0) == pid);
  // Its handler ran: an exit with the shell's code for "terminated" (143), not death by the signal.
  CHECK(WIFEXITED(status));
  CHECK(WEXITSTATUS(status) == 128 + SIGTERM);
  const std::string out = text_of(stopped_log);
  CHECK_THAT(out, Catch::Contains("terminated by a signal") &&
                      Catch::Contains("continue with (any number of ranks):\n  sodaevo evolve --resume " + stopped.string()));
  REQUIRE(run(evolve_args({"--resume", stopped.string()}), log) == 0);
  require_same_results(dir / "whole", stopped);
  fs::remove_all(dir.parent_path());
}

TEST_CASE("an output folder that cannot be created gives a clear error and touches nothing", "[crash]") {
  const fs::path dir = work_dir("unwritable");
  const fs::path config = write_config(dir);
  // A path through a regular file cannot become a folder, whoever runs the test
  // (root ignores permission bits, so a read-only folder would not do).
  const fs::path blocker = dir / "not_a_folder";
  std::ofstream(blocker) << "precious\n";
  const fs::path log = dir / "log.txt";
  CHECK(run(evolve_args({config.string(), "--out", (blocker / "run").string()}), log) == 2);
  const std::string out = text_of(log);
  CHECK_THAT(out, Catch::Contains((blocker / "run").string() + ": cannot create the run folder"));
  CHECK(text_of(blocker) == "precious\n");
  fs::remove_all(dir.parent_path());
}

TEST_CASE("a full disk stops the run with a clear error, loses nothing, and the run resumes", "[crash]") {
  const fs::path dir = work_dir("full");
  const fs::path config = write_config(dir);
  const fs::path log = dir / "log.txt";
  REQUIRE(run(evolve_args({config.string(), "--out", (dir / "whole").string()}), log) == 0);

  // A partial run: its first generations are on disk.
  const fs::path partial = dir / "partial";
  {
    const pid_t pid = spawn(evolve_args({config.string(), "--out", partial.string()}), log);
    while (!fs::exists(partial / "generations" / generation_file_name(3))) {
      std::this_thread::sleep_for(std::chrono::milliseconds(1));
      int status = 0;
      REQUIRE(::waitpid(pid, &status, WNOHANG) == 0);
    }
    ::kill(pid, SIGKILL);
    wait_for(pid);
  }
  const auto before = folder_files(partial);

  // The disk "fills": every file may grow to 4 KiB only, so the next saved
  // generation cannot be written (RLIMIT_FSIZE fails the write with EFBIG where
  // a full disk gives ENOSPC: the same path through the program).
  const fs::path full_log = dir / "full_log.txt";
  std::string command = "trap '' XFSZ; ulimit -f 4; exec";
  for (const std::string& a : evolve_args({"--resume", partial.string()})) command += " '" + a + "'";
  const int code = run({"/bin/sh", "-c", command}, full_log);
  CHECK((code == 1 || code == 2)); // an error exit, not a signal (SIGXFSZ is ignored)
  const std::string out = text_of(full_log);
  CHECK_THAT(out, Catch::Contains("sodaevo: error: " + partial.string()));
  CHECK_THAT(out, Catch::Contains("File too large"));

  // Nothing that was there is lost or damaged; no temporary file is left.
  int temporaries = 0;
  const auto after = folder_files(partial, &temporaries);
  CHECK(temporaries == 0);
  for (const auto& [name, text] : before) {
    INFO("file " << name);
    REQUIRE(after.count(name) == 1);
    // A log may have been rewritten with the rows it had (never fewer: the
    // checkpoint has them) but every file that was complete still is.
    if (name != "generations.csv" && name != "timing.csv") CHECK(after.at(name) == text);
  }
  require_complete_files(partial);

  // With room again, the run resumes and ends as if nothing had happened.
  REQUIRE(run(evolve_args({"--resume", partial.string()}), log) == 0);
  require_same_results(dir / "whole", partial);
  fs::remove_all(dir.parent_path());
}

TEST_CASE("a MAP-Elites run killed with SIGKILL resumes to the uninterrupted archive", "[crash][map-elites]") {
  const fs::path dir = work_dir("map_elites_kill");
  const nlohmann::json config = {
      {"name", "crash-me"},
      {"seed", 5},
      {"algorithm", "map-elites"},
      {"population",
       {{"size", 16},
        {"seed_models", {fs::absolute(sodaevo::test::models_dir() / "dainty_walker.xml").string()}},
        {"random_fraction", 0.75}}},
      {"fitness", {{"frames", 300}, {"settle_frames", 40}}},
      {"map_elites",
       {{"descriptors", {"width", "mass_count"}},
        {"bins", {8, 8}},
        {"ranges", {{40, 300}, {2.5, 10.5}}},
        {"iterations", 30},
        {"batch_size", 12},
        {"snapshot_every", 5}}},
      {"save", {{"checkpoint_every", 3}}}};
  const fs::path config_path = dir / "me.json";
  std::ofstream(config_path) << config.dump(2);
  const fs::path log = dir / "log.txt";
  REQUIRE(run(evolve_args({config_path.string(), "--out", (dir / "whole").string()}), log) == 0);

  // Killed once it has logged a few iterations past a checkpoint, twice, then finished.
  const fs::path killed = dir / "killed";
  auto logged = [&] {
    std::error_code ec;
    if (!fs::exists(killed / "qd.csv", ec)) return 0L;
    const std::string text = text_of(killed / "qd.csv");
    return static_cast<long>(std::count(text.begin(), text.end(), '\n')) - 1;
  };
  int kills = 0;
  for (const long target : {5L, 16L}) {
    const pid_t pid = spawn(kills == 0 ? evolve_args({config_path.string(), "--out", killed.string()})
                                       : evolve_args({"--resume", killed.string()}),
                            log);
    int status = 0;
    pid_t done = 0;
    auto running = [&] { return done == 0 && (done = ::waitpid(pid, &status, WNOHANG)) == 0; };
    while (running() && logged() < target) std::this_thread::sleep_for(std::chrono::microseconds(300));
    if (done == 0) {
      ::kill(pid, SIGKILL);
      if (wait_for(pid) == 128 + SIGKILL) ++kills;
    }
  }
  CHECK(kills >= 1);
  REQUIRE(run(evolve_args({"--resume", killed.string()}), log) == 0);
  for (const char* name : {"qd.csv", "archive.json", "snapshots/archive_00015.json", "snapshots/archive_00030.json"}) {
    INFO(name);
    CHECK(text_of(killed / name) == text_of(dir / "whole" / name));
  }
  const auto elites = [](const fs::path& run) {
    std::vector<std::string> texts;
    for (const fs::directory_entry& e : fs::directory_iterator(run / "elites")) texts.push_back(text_of(e.path()));
    std::sort(texts.begin(), texts.end());
    return texts;
  };
  CHECK(elites(killed) == elites(dir / "whole"));
  fs::remove_all(dir.parent_path());
}
