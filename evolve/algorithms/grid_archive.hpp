// GridArchive: MAP-Elites' archive, the best creature found in each cell of a grid
// over 2 or 3 behaviour descriptors (evolve/problems/descriptors.hpp).
//
// Cells: axis a has bins[a] equal bins over [lo, hi); a value below lo falls in
// the first bin, at or above hi in the last (so every creature has a cell, as in
// pyribs' GridArchive). The cell index is row-major, the first axis slowest:
// cell = (i0 * bins1 + i1) * bins2 + i2.
//
// Noise: a creature's fitness and descriptors are estimates over replicas (runs
// that differ by the sine jitter seed, core/sine_jitter.hpp), and an archive that
// keeps the luckiest draw of each cell is mostly luck (issue 26: the GA's
// champions claim 9 % more than they walk). So a challenger replaces an elite
// only when its mean is higher over a comparable number of replicas, and judge()
// asks for more replicas until the counts are comparable:
//   - empty cell: the challenger enters;
//   - challenger has fewer replicas (and is below the cap): rejected if its mean
//     is not above the elite's (the elite has had at least as many tries), else
//     sample the challenger up to the elite's count (capped);
//   - elite has fewer replicas (and is below the cap): sample the elite up to the
//     challenger's count (capped);
//   - counts comparable (equal, or both at the cap): rejected if the challenger's
//     mean is not strictly higher; else, the first time and below the cap, both
//     are sampled `step` more replicas (a confirmation: a lead on few replicas is
//     often luck), and after that the higher mean wins.
// So elites gather replicas as they are challenged and their estimates sharpen
// over the run, while a challenger that looks worse costs nothing more.
// With one replica and cap 1 this is plain MAP-Elites (higher fitness wins).
// A challenger keeps the cell of its first estimate while it is resampled.
#pragma once

#include <cstddef>
#include <map>
#include <string>
#include <vector>

#include "core/model_def.hpp"
#include "evolve/problems/descriptors.hpp"
#include "evolve/estimators/running_estimate.hpp"

namespace sodaevo {

struct GridAxis {
  Descriptor descriptor = Descriptor::Width;
  int bins = 10;
  double lo = 0.0;
  double hi = 1.0;

  bool operator==(const GridAxis&) const = default;
};

/// The best creature of a cell, with its estimates.
struct ArchiveEntry {
  std::string id;                   ///< unique in the run ("i<iteration>-<index>")
  std::vector<std::string> parents;
  soda::ModelDef creature;          ///< the genome, canonical form
  RunningEstimate fitness;          ///< over its replicas
  double distance = 0.0;            ///< replica 0's (the exact run's) centroid displacement, px
  std::vector<double> descriptors;  ///< one per axis: the mean over the same replicas
  long long iteration = 0;          ///< when it entered the archive
};

enum class Verdict { Enter, Replace, Reject, SampleChallenger, SampleElite, SampleBoth };

struct Judgement {
  Verdict verdict = Verdict::Reject;
  long long replicas = 0; ///< replicas to add to each side sampled (the Sample* verdicts only)
};

/// How far the insertion rule samples: at most `cap` >= 1 replicas a side, `step`
/// >= 1 more each for a confirmation.
struct ResamplePlan {
  long long cap = 1;
  long long step = 1;
};

/// The insertion rule above. `elite` null = empty cell. `confirmed`: this
/// challenger and this elite were already sampled once more together.
Judgement judge(const RunningEstimate* elite, const RunningEstimate& challenger, const ResamplePlan& plan,
                bool confirmed);

/// Quality-diversity metrics of an archive.
///   coverage             filled cells / cells
///   qd_score             sum over filled cells of max(0, elite mean - offset): with
///                        the offset below every fitness this is pyribs' QD-score
///                        (sum of objective - qd_score_offset) and QDax's (sum of
///                        fitness + qd_offset, their offset of opposite sign); the
///                        clamp keeps a backward walker from making a filled cell
///                        worth less than an empty one
///   normalized_qd_score  qd_score / cells (pyribs' norm_qd_score): the mean
///                        offset fitness over every cell, empty ones as 0
///   best, mean           best and mean elite mean fitness (0 when empty)
struct QdMetrics {
  std::size_t cells = 0;
  std::size_t filled = 0;
  double coverage = 0.0;
  double qd_score = 0.0;
  double normalized_qd_score = 0.0;
  double best = 0.0;
  double mean = 0.0;
};

class GridArchive {
 public:
  /// Axes as validated by the config (2 or 3, bins >= 1, lo < hi).
  explicit GridArchive(std::vector<GridAxis> axes);

  [[nodiscard]] const std::vector<GridAxis>& axes() const { return axes_; }
  [[nodiscard]] std::size_t cell_count() const { return cells_; }
  /// The bin of `value` on axis a (clamped to the first and last bin).
  [[nodiscard]] int bin_of(std::size_t axis, double value) const;
  /// The cell of descriptor values, one per axis.
  [[nodiscard]] std::size_t cell_of(const std::vector<double>& values) const;
  /// The cell of a behaviour (the axes' descriptors picked from it).
  [[nodiscard]] std::size_t cell_of(const Behaviour& behaviour) const;
  /// The axes' values picked from every descriptor in enum order (an Evaluation's
  /// descriptors); throws std::invalid_argument if there are too few.
  [[nodiscard]] std::vector<double> axis_values(const std::vector<double>& descriptors) const;
  /// The bin on each axis of a cell.
  [[nodiscard]] std::vector<int> coordinates(std::size_t cell) const;

  [[nodiscard]] const ArchiveEntry* elite(std::size_t cell) const;
  [[nodiscard]] ArchiveEntry* elite(std::size_t cell);
  /// Puts `entry` in `cell` (entering or replacing).
  void place(std::size_t cell, ArchiveEntry entry);
  /// Empties `cell` (an elite that failed on a fresh replica).
  void remove(std::size_t cell) { elites_.erase(cell); }
  /// Filled cells and their elites, in cell order.
  [[nodiscard]] const std::map<std::size_t, ArchiveEntry>& elites() const { return elites_; }
  [[nodiscard]] std::size_t filled() const { return elites_.size(); }

  [[nodiscard]] QdMetrics metrics(double qd_offset) const;

 private:
  std::vector<GridAxis> axes_;
  std::size_t cells_ = 1;
  std::map<std::size_t, ArchiveEntry> elites_;
};

} // namespace sodaevo
