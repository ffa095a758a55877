// Synthetic creatures of a chosen size, for measuring how the step's cost grows
// with the number of links (10 to 100,000 and beyond).
//
// A lattice of masses (spacing 25 px) resting on the floor: per cell a horizontal
// and a vertical spring, a diagonal spring and a diagonal muscle. Muscle phases are
// quantised to k/255 as in files saved by SodaConstructor (8 distinct phases), so
// the sine sharing is what it is on real creatures. The first `links` links in
// column order are kept (the strip stays connected), unused masses are dropped.
#pragma once

#include "core/model_def.hpp"

namespace sodaevo::bench {

soda::ModelDef synthetic_creature(int links);

} // namespace sodaevo::bench
