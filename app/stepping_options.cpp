#include "app/stepping_options.hpp"

#include <string>
#include <vector>

namespace sodaevo::app {

namespace {

std::vector<std::string> integrator_names() {
  std::vector<std::string> names;
  for (soda::Integrator in : soda::kIntegrators) names.push_back(soda::integrator_name(in));
  return names;
}

} // namespace

void add_stepping_options(CLI::App* cmd, SteppingOptions& opt) {
  cmd->add_option("--mode", opt.mode,
                  "Physics mode: soda = one update per frame exactly as the original (default);\n"
                  "continuous = the same model as an ODE stepped with dt = 1/substeps frame")
      ->default_val("soda")
      ->check(CLI::IsMember({"soda", "continuous"}));
  cmd->add_option("--integrator", opt.integrator,
                  "Continuous mode: euler (semi-implicit, order 1; with --substeps 1 equal to soda bit\n"
                  "for bit), verlet (velocity Verlet, order 2), rk4 (Runge-Kutta 4, order 4),\n"
                  "backward-euler (implicit, order 1) or implicit-midpoint (implicit, order 2)")
      ->default_val("euler")
      ->check(CLI::IsMember(integrator_names()));
  cmd->add_option("--substeps", opt.substeps, "Continuous mode: steps per frame (dt = 1/substeps frame)")
      ->default_val(1)
      ->check(CLI::Range(1, soda::kMaxSubsteps));
}

soda::Stepping stepping_of(const SteppingOptions& opt) {
  return soda::stepping_of_names(opt.mode, opt.integrator, opt.substeps);
}

} // namespace sodaevo::app
