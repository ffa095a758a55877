// `sodaevo records`: the Sodarace record book (results/records/, docs/races.md,
// "The record book"). Every race file of the book is raced by each of our racers
// (results/records/candidates/*.xml) and by every public contender
// (results/records/public_contenders.txt), as the original racer races them; each
// file's record is chosen by evolve/runs/record_book.hpp. Writes:
//   README.md      the table: record, its replicas, the best public contender, the
//                  ratio, and how each record was found
//   records.json   the same, machine-readable
//   index.html     each record race played beside the best public contender
// and appends OUT/notes.md (written by hand: what the tables do not say) to README.md.
// A candidate's "how it was found" is the JSON beside it (NAME.json: config, seed,
// generations, wall_seconds, and any note), written by bench/records_search.sh.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "app/commands.hpp"
#include "app/records_page.hpp"
#include "core/input_error.hpp"
#include "core/number_text.hpp"
#include "evolve/runs/record_book.hpp"
#include "formats/atomic_file.hpp"

namespace sodaevo::app {

namespace {

namespace fs = std::filesystem;
using nlohmann::json;

struct RecordsOptions {
  std::string terrains = "models/terrains";
  std::string candidates = "results/records/candidates";
  std::string publics = "results/records/public_contenders.txt";
  std::string out = "results/records";
  int replicas = 16;
  int threads = 0;
  bool page = true;
};

/// The .xml files of a folder, sorted by name.
std::vector<std::string> xml_files(const std::string& dir, const char* what) {
  std::error_code ec;
  if (!fs::is_directory(dir, ec)) throw soda::InputError(dir + ": expected a folder of " + what + ", got none there");
  std::vector<std::string> out;
  for (const fs::directory_entry& e : fs::directory_iterator(dir)) {
    if (e.is_regular_file() && e.path().extension() == ".xml") out.push_back(e.path().string());
  }
  std::sort(out.begin(), out.end());
  if (out.empty()) throw soda::InputError(dir + ": expected " + std::string(what) + " (.xml), got no .xml file");
  return out;
}

/// The public contenders' list: one path a line (relative to the list's folder's
/// project, i.e. to the working directory), '#' starts a comment.
std::vector<std::string> read_list(const std::string& list) {
  std::ifstream in(list);
  if (!in) throw soda::InputError(list + ": cannot read the list of public contenders");
  std::vector<std::string> out;
  std::string line;
  for (int number = 1; std::getline(in, line); ++number) {
    line = line.substr(0, line.find('#'));
    while (!line.empty() && std::isspace(static_cast<unsigned char>(line.back()))) line.pop_back();
    while (!line.empty() && std::isspace(static_cast<unsigned char>(line.front()))) line.erase(0, 1);
    if (line.empty()) continue;
    if (!fs::is_regular_file(line)) {
      throw soda::InputError(list + ":" + std::to_string(number) + ": expected an existing contender file, got \"" +
                             line + "\"");
    }
    out.push_back(line);
  }
  return out;
}

/// NAME.json beside a candidate NAME.xml, or null.
json how_found(const std::string& candidate) {
  const fs::path side = fs::path(candidate).replace_extension(".json");
  if (!fs::exists(side)) return nullptr;
  std::ifstream in(side);
  try {
    return json::parse(in);
  } catch (const json::exception& ex) {
    throw soda::InputError(side.string() + ": expected the JSON of how the racer was found: " + ex.what());
  }
}

std::string found_text(const json& found) {
  if (found.is_null()) return "-";
  std::ostringstream o;
  if (found.contains("config")) o << "`" << found["config"].get<std::string>() << "`";
  if (found.contains("seed")) o << ", seed " << found["seed"];
  if (found.contains("generations")) o << ", " << found["generations"] << " generations";
  if (found.contains("wall_seconds")) {
    const double seconds = found["wall_seconds"].get<double>();
    if (seconds < 90.0) o << ", " << static_cast<long long>(seconds + 0.5) << " s";
    else o << ", " << static_cast<long long>(seconds / 60.0 + 0.5) << " min";
  }
  if (found.contains("note")) o << "; " << found["note"].get<std::string>();
  return o.str();
}

json replicas_json(const ReplicaRecord& r) {
  return {{"n", r.summary.n},
          {"median", r.summary.median},
          {"interval95", {r.summary.interval95_low, r.summary.interval95_high}},
          {"finished", r.finished_share}};
}


void write_book(const RecordBook& book, const RecordBookInputs& in, const RecordsOptions& opt) {
  const fs::path out(opt.out);
  fs::create_directories(out);
  json records = json::array();
  std::ostringstream md;
  md << "# The Sodarace record book\n\n"
     << "Written by `sodaevo records` (docs/races.md, \"The record book\"): every race file raced by our racers ("
     << "`" << opt.candidates << "`) and by every public contender (`" << opt.publics << "`, " << in.publics.size()
     << " files), exactly as the original racer races them. A record is our fastest finisher whose " << opt.replicas
     << " jittered replicas (another machine's sine) finish at least 90 % of the time. Frames are the exact "
     << "result; the replicas give the median and the 95 % prediction interval. Ratio: record / best public, where "
     << "the public one finishes. The races play in [index.html](index.html).\n\n"
     << "| race file | record | frames | replicas: median [95 % interval], finished | best public contender | its frames | ratio | how it was found |\n"
     << "|---|---|---:|---|---|---:|---:|---|\n";
  int records_held = 0;
  for (const FileRecord& f : book.files) {
    json j = {{"race_file", file_name_of(f.race_file)}, {"timeout", f.timeout}};
    md << "| " << file_name_of(f.race_file) << " | ";
    if (f.record >= 0) {
      const RaceEntry& r = f.candidates[static_cast<std::size_t>(f.record)];
      const ReplicaRecord& rep = f.record_replicas;
      records_held += f.qualified ? 1 : 0;
      char reps[128];
      std::snprintf(reps, sizeof reps, "%.1f [%.1f, %.1f], %.0f %%", rep.summary.median, rep.summary.interval95_low,
                    rep.summary.interval95_high, 100.0 * rep.finished_share);
      md << "`" << r.file << "` | **" << race_result_text(r.outcome) << "** | " << reps << (f.qualified ? "" : " (not qualified)")
         << " | ";
      j["racer"] = r.file;
      j["frames"] = r.outcome.result;
      j["qualified"] = f.qualified;
      j["replicas_finished"] = rep.finished_share;
      j["replicas"] = replicas_json(rep);
      j["how_found"] = how_found(r.file);
    } else {
      md << "none of ours finishes | - | - | ";
      j["racer"] = nullptr;
      j["frames"] = nullptr;
    }
    if (f.best_public >= 0) {
      const RaceEntry& p = f.publics[static_cast<std::size_t>(f.best_public)];
      md << "`" << p.file << "` (" << p.name << ") | " << race_result_text(p.outcome) << " | ";
      j["best_public"] = p.file;
      j["best_public_frames"] = p.outcome.result;
      j["best_public_finished"] = p.outcome.finished;
      if (f.record >= 0 && p.outcome.finished) {
        const double ratio = f.candidates[static_cast<std::size_t>(f.record)].outcome.result / p.outcome.result;
        char text[32];
        std::snprintf(text, sizeof text, "%.3f", ratio);
        md << text;
        j["ratio"] = ratio;
      } else {
        md << "-";
      }
    } else {
      md << "- | - | -";
    }
    md << " | " << (f.record >= 0 ? found_text(how_found(f.candidates[static_cast<std::size_t>(f.record)].file)) : "-")
       << " |\n";
    records.push_back(std::move(j));
  }
  json generalist = nullptr;
  if (book.generalist.candidate >= 0) {
    const std::string& racer = in.candidates[static_cast<std::size_t>(book.generalist.candidate)];
    md << "\n" << records_held << " of " << book.files.size() << " files hold a qualified record.\n\n"
       << "## The generalist\n\n`" << racer << "` finishes " << book.generalist.files_finished << " of "
       << book.files.size() << " files (how it was found: " << found_text(how_found(racer)) << ").\n\n"
       << "| race file | frames | replicas: median [95 % interval], finished |\n|---|---:|---|\n";
    json frames = json::object(), finished = json::object();
    for (std::size_t i = 0; i < book.files.size(); ++i) {
      const FileRecord& f = book.files[i];
      const RaceEntry& e = f.candidates[static_cast<std::size_t>(book.generalist.candidate)];
      const ReplicaRecord& rep = book.generalist.replicas[i];
      md << "| " << file_name_of(f.race_file) << " | " << (e.no_result.empty() ? race_result_text(e.outcome) : "no result") << " | ";
      if (!rep.outcomes.empty()) {
        char reps[128];
        std::snprintf(reps, sizeof reps, "%.1f [%.1f, %.1f], %.0f %%", rep.summary.median, rep.summary.interval95_low,
                      rep.summary.interval95_high, 100.0 * rep.finished_share);
        md << reps;
        finished[file_name_of(f.race_file)] = rep.finished_share;
      }
      md << " |\n";
      frames[file_name_of(f.race_file)] = e.no_result.empty() ? json(e.outcome.result) : json(nullptr);
    }
    generalist = {{"racer", racer},
                  {"files_finished", book.generalist.files_finished},
                  {"frames", frames},
                  {"replicas_finished", finished}};
  }
  if (const fs::path notes = out / "notes.md"; fs::exists(notes)) { // what the tables do not say, by hand
    std::ifstream in(notes);
    md << "\n" << in.rdbuf();
  }
  md << "\nReproduce: `build/sodaevo records` (about a minute; `--help` for the folders it reads).\n";
  const json doc = {{"records", records},
                    {"generalist", generalist},
                    {"replicas", opt.replicas},
                    {"jitter", in.jitter},
                    {"bar_engine", "2004"}};
  soda::write_file_atomically(out / "records.json", doc.dump(2) + "\n");
  soda::write_file_atomically(out / "README.md", md.str());
  if (opt.page) soda::write_file_atomically(out / "index.html", records_page(book));
  std::printf("%d of %zu race files hold a qualified record; generalist finishes %d; wrote %s\n", records_held,
              book.files.size(), book.generalist.files_finished, out.string().c_str());
}

void run_records(const RecordsOptions& opt) {
  RecordBookInputs in;
  in.race_files = xml_files(opt.terrains, "race files");
  in.candidates = xml_files(opt.candidates, "racers");
  in.publics = read_list(opt.publics);
  in.replicas = opt.replicas;
  in.threads = opt.threads;
  std::vector<std::string> warnings;
  const RecordBook book = compile_record_book(in, warnings, [](int done, int total, const std::string& what) {
    std::fprintf(stderr, "\r[%3d/%3d] %-70.70s", done, total, what.c_str());
    if (done == total) std::fprintf(stderr, "\n");
    std::fflush(stderr);
  });
  std::sort(warnings.begin(), warnings.end());
  warnings.erase(std::unique(warnings.begin(), warnings.end()), warnings.end());
  for (const std::string& w : warnings) std::cerr << "sodaevo: " << w << '\n';
  write_book(book, in, opt);
}

} // namespace

void add_records_command(CLI::App& app) {
  auto opt = std::make_shared<RecordsOptions>();
  CLI::App* cmd = app.add_subcommand(
      "records",
      "The Sodarace record book: races every race file (--terrains) with each of our racers\n"
      "(--candidates) and every public contender (--public), exactly as the original racer, and\n"
      "writes README.md (the table), records.json and index.html (each record race beside the\n"
      "best public contender) into --out. A file's record is our fastest finisher whose jittered\n"
      "replicas finish at least 90 % of the time. Run from the project folder (the defaults are\n"
      "relative to it). Racers come from `bench/records_search.sh` (docs/races.md).");
  cmd->add_option("--terrains", opt->terrains, "Folder of the race files of the book")->capture_default_str();
  cmd->add_option("--candidates", opt->candidates,
                  "Folder of our racers (.xml; NAME.json beside one says how it was found)")
      ->capture_default_str();
  cmd->add_option("--public", opt->publics, "List of public contender files, one a line ('#' comments)")
      ->capture_default_str();
  cmd->add_option("--out", opt->out, "Folder to write the book into")->capture_default_str();
  cmd->add_option("--replicas", opt->replicas, "Jittered replicas per record racer and file")
      ->capture_default_str()
      ->check(CLI::Range(2, 4096));
  cmd->add_option("--threads", opt->threads, "Threads for the replicas (0: all cores)")->check(CLI::Range(0, 1024));
  cmd->add_flag("!--no-page", opt->page, "Do not write index.html");
  cmd->callback([opt] { run_records(*opt); });
}

} // namespace sodaevo::app
