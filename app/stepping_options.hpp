// The physics-mode options shared by the commands that run a model (simulate,
// render): --mode, --integrator, --substeps, with one help text and one check, so
// every command names and validates a setting the same way (core/stepping.hpp).
#pragma once

#include <string>

#include <CLI/CLI.hpp>

#include "core/stepping.hpp"

namespace sodaevo::app {

struct SteppingOptions {
  std::string mode = "soda";
  std::string integrator = "euler";
  int substeps = 1;
};

/// Registers --mode, --integrator and --substeps on `cmd`, writing into `opt`.
void add_stepping_options(CLI::App* cmd, SteppingOptions& opt);

/// The setting the options name. Throws soda::InputError for an inconsistent one
/// (e.g. --substeps without --mode continuous).
soda::Stepping stepping_of(const SteppingOptions& opt);

} // namespace sodaevo::app
