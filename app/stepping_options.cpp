#include "app/stepping_options.hpp"

#include "core/input_error.hpp"

namespace sodaevo::app {

void add_stepping_options(CLI::App* cmd, SteppingOptions& opt) {
  cmd->add_option("--mode", opt.mode,
                  "Physics mode: soda = one update per frame exactly as the original (default);\n"
                  "continuous = the same model as an ODE stepped with dt = 1/substeps frame")
      ->default_val("soda")
      ->check(CLI::IsMember({"soda", "continuous"}));
  cmd->add_option("--integrator", opt.integrator,
                  "Continuous mode: euler (semi-implicit, order 1; with --substeps 1 equal to soda bit\n"
                  "for bit), verlet (velocity Verlet, order 2) or rk4 (Runge-Kutta 4, order 4)")
      ->default_val("euler")
      ->check(CLI::IsMember({"euler", "verlet", "rk4"}));
  cmd->add_option("--substeps", opt.substeps, "Continuous mode: steps per frame (dt = 1/substeps frame)")
      ->default_val(1)
      ->check(CLI::Range(1, soda::kMaxSubsteps));
}

soda::Stepping stepping_of(const SteppingOptions& opt) {
  soda::Stepping st;
  const auto mode = soda::parse_mode(opt.mode);
  if (!mode) throw soda::InputError("--mode: expected soda or continuous, got '" + opt.mode + "'");
  const auto integrator = soda::parse_integrator(opt.integrator);
  if (!integrator) throw soda::InputError("--integrator: expected euler, verlet or rk4, got '" + opt.integrator + "'");
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
