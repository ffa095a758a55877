// What must hold for ANY input to the readers, shared by the fuzz targets and the
// test suite (which replays every regression file in tests/data/fuzz_regressions).
//
// Each check feeds bytes to one reader. Rejecting them with soda::InputError is
// fine; so is accepting them. Anything else is a bug: another exception type, a
// crash or hang (the sanitizers and libFuzzer see those), or an accepted input
// that breaks a documented round trip — that is thrown as PropertyViolation.
#pragma once

#include <stdexcept>
#include <string>
#include <string_view>

namespace sodaevo::fuzz {

struct PropertyViolation : std::logic_error {
  using std::logic_error::logic_error;
};

/// The outcome of a reader on one input.
struct CheckResult {
  bool accepted = false;
  std::string error; ///< the InputError message when rejected
};

/// soda::read_model_text (v1 <model>, v2 object graph, <race>): an accepted model
/// must write as canonical v1 and read back to canonical_form of itself, and
/// build_model must accept it or reject it with InputError.
CheckResult check_model_xml(std::string_view bytes);

/// parse_run_config: an accepted config must round-trip through to_json.
CheckResult check_run_config(std::string_view bytes);

/// parse_checkpoint (checkpoint.json with its embedded <generation>): an accepted
/// checkpoint's generation must write and read back with the same creatures.
CheckResult check_checkpoint(std::string_view bytes);

} // namespace sodaevo::fuzz
