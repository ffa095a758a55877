// The Sodarace racer's contender filter (FilterScaledSquare; docs/physics.md, "The contender"; golden
// set tests/data/terrain/components): what the racer keeps of a contender before it
// places it in its lane, and the scale it gives it.
//
// The racer rejects a contender whose last <nodes> entry is a fixed node (no
// result), drops fixed nodes and every link touching one, keeps one connected piece
// of the rest (the most masses; a tie goes to the piece holding the earliest mass)
// and scales that piece to half its container's height. A creature that falls apart
// therefore races as its largest piece alone.
#pragma once

#include <string>
#include <vector>

#include "input_error.hpp"
#include "model_def.hpp"

namespace soda {

/// The racer gives no result for this contender (its filter throws, or this port
/// cannot say what the racer does with it). The message names the contender.
class ContenderRejected : public InputError {
 public:
  using InputError::InputError;
};

/// The connected pieces of a contender's masses (fixed nodes and the links touching
/// them left out; springs, muscles and fixed bars between two masses join them).
struct ContenderPieces {
  int masses = 0;                ///< free masses in the file
  int pieces = 0;                ///< connected pieces among them
  std::vector<int> kept;         ///< node indices of the kept piece, file order
  [[nodiscard]] bool connected() const { return pieces <= 1; }
};

/// The pieces of `c` and the one the racer keeps (the most masses; ties: the piece
/// holding the earliest mass). No masses: kept is empty.
ContenderPieces contender_pieces(const ModelDef& c);

/// The contender after the filter: the kept masses (file order) and the links
/// between them (file order, a/b as written, indices into `masses`), scaled by
/// `scale` about ((min x + max x)/2, max y) of the kept masses; not yet placed.
struct FilteredContender {
  std::vector<NodeDef> masses;
  std::vector<LinkDef> links;
  double scale = 1.0; ///< (H/2)/sqrt(sum of Lmax^2) over the kept links; +inf when that sum is 0
  ContenderPieces pieces;
};

/// Filters and scales `c` as the racer does. Throws ContenderRejected, naming
/// `name`, where the racer gives no result: no nodes, or a fixed node last in
/// <nodes>; also for a kept fixed bar from a mass to itself (what the racer does
/// with one is not known to this port). A sum of Lmax^2 of 0 is no error: scale +inf, a NaN contender (the
/// racer then reports its timeout formula).
FilteredContender filter_contender(const ModelDef& c, const std::string& name);

} // namespace soda
