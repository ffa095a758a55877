#include "bench/stress_report.hpp"

#include <sstream>

#include "core/number_text.hpp"
#include "formats/atomic_file.hpp"

namespace sodaevo::bench {

StressFiles write_stress_files(const std::filesystem::path& out, const std::vector<StressCounts>& counts,
                               const StressOptions& options, const std::string& command, double seconds) {
  StressFiles files;
  std::ostringstream csv, md;
  csv << "stepping,creatures_tried,frames_per_creature,frames_stepped,diverged_non_finite,diverged_energy,escaped\n";
  md << "Measured with `" << command << "` (" << options.threads << " threads, "
     << soda::format_printf("%.6g", seconds) << " s).\n\n";
  md << "| stepping | creatures tried | frames stepped | flagged: non-finite state | flagged: energy runaway | escaped |\n";
  md << "|---|---:|---:|---:|---:|---:|\n";
  std::ostringstream notes;
  for (const auto& c : counts) {
    csv << c.stepping << ',' << c.tried << ',' << options.frames << ',' << c.frames_stepped << ','
        << c.diverged_non_finite << ',' << c.diverged_energy << ',' << c.escaped << '\n';
    md << "| " << c.stepping << " | " << c.tried << " | " << c.frames_stepped << " | " << c.diverged_non_finite << " | "
       << c.diverged_energy << " | " << c.escaped << " |\n";
    if (c.escaped) {
      files.escaped = true;
      notes << "\nFirst escape (" << c.stepping << "): " << c.first_escape << "\n";
    }
    if (!c.example_diverged.empty()) notes << "\nExample flagged (" << c.stepping << "): " << c.example_diverged << "\n";
  }
  md << notes.str();
  files.markdown = md.str();
  std::filesystem::create_directories(out);
  soda::write_file_atomically(out / "stress.csv", csv.str());
  soda::write_file_atomically(out / "stress.md", files.markdown);
  return files;
}

} // namespace sodaevo::bench
