// Which sine made a run folder, and what replay, report and --resume say when it
// is not this engine's (core/sine_identity.hpp says why it matters).
//
// manifest.json holds
//   "sine": "java-hotspot-x86_64"     the sine the run is made with now
//   "sine_changes": [{"generation": 12, "from": "glibc-x86_64-fma",
//                     "to": "java-hotspot-x86_64", "resumed": "2026-..."}]
//                                     only if `evolve --resume-other-sine` changed
//                                     it: generation 12 (the checkpoint, scored
//                                     again) and every later one were made with `to`
// A manifest without "sine" was written before the engine recorded it: glibc's.
// checkpoint.json and archive_checkpoint.json hold "sine" too: the state a resume
// continues from says itself what scored it, even if the run died between a
// manifest change and the checkpoint after it.
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace sodaevo {

struct SineChange {
  int generation = 0; ///< the first generation (MAP-Elites: iteration) made with `to`
  std::string from, to;
};

struct RunSine {
  bool recorded = false;           ///< manifest.json names the sine ("sine")
  std::string sine;                ///< the sine the run is made with now (kGlibcSine if not recorded)
  std::vector<SineChange> changes; ///< in order of generation

  /// The sine generation `g` was made with.
  [[nodiscard]] std::string of_generation(int g) const;
  /// Whether every generation was made with this engine's sine.
  [[nodiscard]] bool all_engine() const;
  /// One line for the report: "Java's Math.sin (java-hotspot-x86_64)", or per
  /// range of generations when the run changed sine.
  [[nodiscard]] std::string summary() const;
};

/// The sine record of RUN/manifest.json. A folder without a manifest (a run killed
/// before writing it scored nothing) reads as not recorded. Throws InputError
/// naming the file for invalid JSON or a "sine" / "sine_changes" of the wrong shape.
RunSine read_run_sine(const std::filesystem::path& run_dir);

/// A sine by name for people: "Java's Math.sin (java-hotspot-x86_64)", "glibc's sin
/// (glibc-x86_64-fma, the engine before 2026-11-27)", or "a sine this sodaevo does
/// not know ('x')".
std::string sine_description(std::string_view sine);

/// What differs and why, for `subject_made` ("this run was made", "generation 3 of
/// this run was made") with `made_with` (`recorded`: named in the files, not
/// presumed from their silence): "SUBJECT_MADE with ...; this engine computes ...,
/// so trajectories part ...: re-simulated fitnesses will differ from the logged
/// ones". Empty if `made_with` is the engine's sine.
std::string other_sine_note(const std::string& subject_made, std::string_view made_with, bool recorded);

/// other_sine_note for a whole run folder: empty if every generation was made
/// with this engine's sine; for a run that changed sine, about the generations
/// before the change.
std::string run_sine_note(const RunSine& run);

/// The state `evolve --resume` continues from and the sine that scored it.
struct ResumePoint {
  int generation = 0;  ///< the checkpoint's generation (MAP-Elites: iteration)
  std::string sine;    ///< which sine scored it, by the checkpoint and the manifest
  bool recorded = false;
  std::string file;    ///< the file that names it (or fails to)
};

/// The resume point of a run folder; nullopt without a checkpoint (nothing was
/// scored: nothing to mix). The checkpoint's own "sine" and what the manifest says
/// of its generation must both be the engine's for `sine` to be; the first that
/// is not is reported. `map_elites`: archive_checkpoint.json's iteration.
std::optional<ResumePoint> resume_point(const std::filesystem::path& run_dir, bool map_elites);

/// Records in manifest.json that the run goes on with this engine's sine from
/// `generation` on (scored again there), having been made with `from`. Repeating
/// the same change (a resume that died before its next checkpoint) adds nothing.
void record_sine_change(const std::filesystem::path& run_dir, int generation, const std::string& from);

} // namespace sodaevo
