// Stepping: which physics mode and integrator advance a scene, chosen at run time.
//
// Two modes (docs/continuous-mode.md): `soda`, one update per frame
// exactly as the original (step.hpp), and `continuous`, the same model read as an
// ODE and stepped with dt = 1/substeps frame by one of several integrators
// (continuous_step.hpp). The command line, the GA config and the benchmarks all
// name a setting the same way, so the names live here once.
#pragma once

#include <iterator>
#include <memory>
#include <optional>
#include <string>

#include "enum_names.hpp"
#include "model.hpp"

namespace soda {

enum class PhysicsMode { Soda, Continuous };

/// Integrators of the continuous mode (continuous_step.hpp has the details):
/// semi-implicit Euler (order 1; dt = 1 is the original scheme), velocity Verlet
/// (order 2) and classic Runge-Kutta 4 (order 4) for the smooth forces; and the
/// implicit backward Euler (order 1) and implicit midpoint rule (order 2), Newton
/// solves with a sparse factorisation (implicit_step.hpp).
enum class Integrator { Euler, Verlet, Rk4, BackwardEuler, ImplicitMidpoint };

/// The names of the modes and integrators (enum_names.hpp): the config's
/// /fitness/mode and /fitness/integrator, the commands' --mode and --integrator and
/// the Python module's keywords all read these.
inline constexpr EnumName<PhysicsMode> kPhysicsModeNames[] = {{PhysicsMode::Soda, "soda"},
                                                              {PhysicsMode::Continuous, "continuous"}};
inline constexpr EnumName<Integrator> kIntegratorNames[] = {{Integrator::Euler, "euler"},
                                                            {Integrator::Verlet, "verlet"},
                                                            {Integrator::Rk4, "rk4"},
                                                            {Integrator::BackwardEuler, "backward-euler"},
                                                            {Integrator::ImplicitMidpoint, "implicit-midpoint"}};

/// Every integrator, in the order of its name table (for option lists and sweeps).
inline constexpr Integrator kIntegrators[] = {kIntegratorNames[0].value, kIntegratorNames[1].value,
                                              kIntegratorNames[2].value, kIntegratorNames[3].value,
                                              kIntegratorNames[4].value};
static_assert(std::size(kIntegrators) == std::size(kIntegratorNames));

/// Largest sub-step count accepted (dt = 1/4096 frame): far below any useful dt,
/// and a bound that keeps a typo from running for days.
inline constexpr int kMaxSubsteps = 4096;

struct Stepping {
  PhysicsMode mode = PhysicsMode::Soda;
  Integrator integrator = Integrator::Euler; ///< continuous mode only
  int substeps = 1;                           ///< continuous mode only: dt = 1/substeps frame

  bool operator==(const Stepping&) const = default;
};

std::string mode_name(PhysicsMode mode);       ///< "soda" | "continuous"
std::string integrator_name(Integrator integrator); ///< "euler" | "verlet" | "rk4" | "backward-euler" | "implicit-midpoint"
std::optional<PhysicsMode> parse_mode(const std::string& name);
std::optional<Integrator> parse_integrator(const std::string& name);

/// Short label: "soda", "euler/4", "rk4/16".
std::string stepping_label(const Stepping& stepping);

/// Throws InputError unless substeps is in [1, kMaxSubsteps].
void validate_stepping(const Stepping& stepping);

/// The setting named by a mode ("soda" | "continuous"), an integrator's name and a
/// sub-step count, as the commands' --mode, --integrator and --substeps and the
/// Python module's keywords name it. Throws InputError for an unknown name or an
/// inconsistent setting (an integrator or sub-steps other than euler/1 in soda
/// mode); messages name the setting as `prefix` + "mode" etc. ("--mode").
Stepping stepping_of_names(const std::string& mode, const std::string& integrator, int substeps,
                           const std::string& prefix = "--");

class ContinuousStepper;
class FastStepper;

/// Steps a model frame by frame in the chosen mode (holds the continuous
/// stepper's scratch space, so make one per run, not one per frame).
class FrameStepper {
public:
  /// Throws InputError for a bad setting. `model` must outlive the stepper.
  /// `frame_budget`: frames the caller means to run (the soda mode's FastStepper
  /// analyses the scene for them; running more is still exact). Soda mode runs the
  /// FastStepper, or the plain reference step (step.hpp) if `reference_step`; both
  /// give the same bits.
  FrameStepper(const Model& model, const Stepping& stepping, long long frame_budget = 0,
               bool reference_step = false);
  ~FrameStepper();
  FrameStepper(FrameStepper&&) noexcept;
  FrameStepper& operator=(FrameStepper&&) = delete;
  FrameStepper(const FrameStepper&) = delete;
  FrameStepper& operator=(const FrameStepper&) = delete;

  void step(State& state);
  void run(State& state, long long frames);

private:
  const Model& model_;
  std::unique_ptr<ContinuousStepper> continuous_; ///< continuous mode
  std::unique_ptr<FastStepper> fast_;             ///< soda mode, unless the reference step is asked for
};


} // namespace soda
