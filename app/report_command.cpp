// sodaevo report: one self-contained HTML page for a run folder.
#include <filesystem>
#include <iostream>
#include <memory>
#include <string>

#include "app/archive_report.hpp"
#include "app/commands.hpp"
#include "app/run_report.hpp"

namespace sodaevo::app {

namespace {

struct ReportCommandOptions {
  std::string run;
  std::string out;
  ReportOptions report;
};

} // namespace

void add_report_command(CLI::App& app) {
  auto opt = std::make_shared<ReportCommandOptions>();
  CLI::App* cmd = app.add_subcommand(
      "report",
      "Write one self-contained HTML page (no network) about a run: its config; best, mean and\n"
      "median fitness per generation and the invalid and diverged counts as charts; the best\n"
      "creatures with distance and speed; animations of the champion and of the best of a few\n"
      "generations next to the Dainty Walker under the same fitness settings. `evolve` writes\n"
      "RUN/report.html itself at the end of a run and every few generations.\n"
      "A MAP-Elites run gets RUN/archive.html instead: the archive as heat maps (click a cell to\n"
      "play its elite), QD-score and coverage over the run.\n"
      "A run made with another muscle sine than this engine's (manifest.json; runs made before\n"
      "the engine computed Java's Math.sin used glibc's sin) is said to be so, here and on the page:\n"
      "what the report simulates again differs from what the run logged.");
  cmd->add_option("run", opt->run, "Run folder")->required()->check(non_empty_path());
  cmd->add_option("-o,--out", opt->out, "Output .html (default RUN/report.html)");
  cmd->add_option("--rows", opt->report.table_rows, "Best distinct creatures listed in the table")
      ->default_val(10)
      ->check(CLI::Range(1, 1000));
  cmd->add_option("--generations", opt->report.chosen_generations,
                  "Generations, evenly spaced from first to last, whose best is animated besides the champion")
      ->default_val(3)
      ->check(CLI::Range(1, 20));
  cmd->add_option("--samples", opt->report.max_samples,
                  "Pictures kept per animation (the trial is sampled every k frames to stay under it)")
      ->default_val(400)
      ->check(CLI::Range(2, 100000));
  cmd->callback([opt] {
    const bool archive = has_archive(opt->run); // a MAP-Elites run: its archive page
    const std::filesystem::path out = !opt->out.empty() ? std::filesystem::path(opt->out)
                                      : archive         ? default_archive_report_path(opt->run)
                                                        : default_report_path(opt->run);
    if (archive) write_archive_report(opt->run, out);
    else write_run_report(opt->run, out, opt->report);
    // Said in the terminal too (once the page is written: not before an error about
    // the folder): a user comparing figures should not have to find it in the page.
    if (const std::string note = report_sine_note(opt->run); !note.empty()) std::cout << "note: " << note << ".\n";
    std::cout << "wrote " << out.string() << "\n";
  });
}

} // namespace sodaevo::app
