#include "app/stepping_options.hpp"

#include <string>
#include <vector>

#include "core/input_error.hpp"

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
  soda::Stepping st;
  const auto mode = soda::parse_mode(opt.mode);
  if (!mode) throw soda::InputError("--mode: expected soda or continuous, got '" + opt.mode + "'");
  const auto integrator = soda::parse_integrator(opt.integrator);
  if (!integrator) {
    std::string expected;
    for (const std::string& name : integrator_names()) expected += (expected.empty() ? "" : ", ") + name;
    throw soda::InputError("--integrator: expected one of " + expected + ", got '" + opt.integrator + "'");
  }
  st.mode = *mode;
  st.integrator = *integrator;
  st.substeps = opt.substeps;
  if (st.mode == soda::PhysicsMode::Soda && (st.substeps != 1 || st.integrator != soda::Integrator::Euler)) {
    throw soda::InputError("--substeps and --integrator need --mode continuous (soda is one Euler update per frame)");
  }
  soda::validate_stepping(st);
  return st;
}

} // namespace sodaevo::app
