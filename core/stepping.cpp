#include "stepping.hpp"

#include "continuous_step.hpp"
#include "fast_step.hpp"
#include "input_error.hpp"
#include "step.hpp"

namespace soda {

std::string mode_name(PhysicsMode mode) { return name_of(kPhysicsModeNames, mode); }

std::string integrator_name(Integrator integrator) { return name_of(kIntegratorNames, integrator); }

std::optional<PhysicsMode> parse_mode(const std::string& name) { return value_of(kPhysicsModeNames, name); }

std::optional<Integrator> parse_integrator(const std::string& name) { return value_of(kIntegratorNames, name); }

std::string stepping_label(const Stepping& s) {
  if (s.mode == PhysicsMode::Soda) return "soda";
  return integrator_name(s.integrator) + "/" + std::to_string(s.substeps);
}

void validate_stepping(const Stepping& s) {
  if (s.substeps < 1 || s.substeps > kMaxSubsteps) {
    throw InputError("substeps: expected an integer in [1, " + std::to_string(kMaxSubsteps) + "], got " +
                     std::to_string(s.substeps));
  }
}

Stepping stepping_of_names(const std::string& mode_text, const std::string& integrator_text, int substeps,
                           const std::string& prefix) {
  const auto mode = parse_mode(mode_text);
  if (!mode) throw InputError(prefix + "mode: expected soda or continuous, got '" + mode_text + "'");
  const auto integrator = parse_integrator(integrator_text);
  if (!integrator) {
    std::string expected;
    for (Integrator in : kIntegrators) expected += (expected.empty() ? "" : ", ") + integrator_name(in);
    throw InputError(prefix + "integrator: expected one of " + expected + ", got '" + integrator_text + "'");
  }
  Stepping st;
  st.mode = *mode;
  st.integrator = *integrator;
  st.substeps = substeps;
  if (st.mode == PhysicsMode::Soda && (st.substeps != 1 || st.integrator != Integrator::Euler)) {
    throw InputError(prefix + "substeps and " + prefix + "integrator need " + prefix +
                     "mode continuous (soda is one Euler update per frame)");
  }
  validate_stepping(st);
  return st;
}

FrameStepper::FrameStepper(const Model& model, const Stepping& stepping, long long frame_budget, bool reference_step)
    : model_(model) {
  validate_stepping(stepping);
  if (stepping.mode == PhysicsMode::Continuous) {
    continuous_ = std::make_unique<ContinuousStepper>(model, ContinuousSettings{stepping.integrator, stepping.substeps});
  } else if (!reference_step) {
    fast_ = std::make_unique<FastStepper>(model, frame_budget);
  }
}

FrameStepper::~FrameStepper() = default;
FrameStepper::FrameStepper(FrameStepper&&) noexcept = default;

void FrameStepper::step(State& state) {
  if (continuous_) continuous_->step(state);
  else if (fast_) fast_->step(state);
  else soda::step(model_, state);
}

void FrameStepper::run(State& state, long long frames) {
  if (continuous_) continuous_->run(state, frames);
  else if (fast_) fast_->run(state, frames);
  else soda::run(model_, state, frames);
}

} // namespace soda
