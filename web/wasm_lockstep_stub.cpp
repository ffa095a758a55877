// LockstepBatch in WebAssembly: its kernels are AVX-512 or AVX2
// (core/lockstep_kernels_*.cpp), which WebAssembly has not, so usable() is false and BatchStepper and the race
// lanes never build one (they fuse instead: the same bits). Compiled instead of
// core/lockstep_batch.cpp and core/lockstep_plan.cpp by web/build_wasm.sh.
#include <stdexcept>

#include "core/lockstep_batch.hpp"

namespace soda {

struct LockstepBatch::Data {};

namespace {
[[noreturn]] void absent() { throw std::logic_error("LockstepBatch: no AVX2 or AVX-512 in WebAssembly"); }
} // namespace

bool LockstepBatch::usable(SimdLevel) { return false; }
SimdLevel LockstepBatch::level_for(SimdLevel level) { return level; }
bool LockstepBatch::can_take(const Model&) { return false; }
bool LockstepBatch::same_shape(const Model&, const Model&) { return false; }
LockstepBatch::LockstepBatch(const std::vector<const Model*>&, SimdLevel) { absent(); }
LockstepBatch LockstepBatch::of_shapes(const std::vector<std::vector<const Model*>>&, SimdLevel) { absent(); }
SimdLevel LockstepBatch::level() const { absent(); }
LockstepBatch::~LockstepBatch() = default;
LockstepBatch::LockstepBatch(LockstepBatch&&) noexcept = default;
LockstepBatch& LockstepBatch::operator=(LockstepBatch&&) noexcept = default;
void LockstepBatch::run(State* const*, long long) { absent(); }
long long LockstepBatch::run_until(State* const*, long long, const StopFn&, std::vector<long long>&) { absent(); }
int LockstepBatch::size() const { absent(); }
int LockstepBatch::group_count() const { absent(); }
int LockstepBatch::sine_columns(int) const { absent(); }
bool LockstepBatch::shares_sines(int) const { absent(); }
long long LockstepBatch::bar_rules_run() const { absent(); }
void LockstepBatch::step(State* const*, long long) { absent(); }
long long LockstepBatch::step_until(State* const*, long long, const StopFn*, long long*) { absent(); }

} // namespace soda
