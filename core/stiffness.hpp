// The stiffness matrix of a state: K = -d(link accelerations)/d(positions) of the
// free masses, the linearisation of the engine's link impulse (docs/physics.md, Part 1) around
// the state, springs and muscles at their current targets (the wave phase of the
// state), unit masses.
//
// Why: the stability of one update per frame, and of every continuous integrator,
// is a question about K's largest eigenvalue (stability.hpp), and the implicit
// integrators solve with K in their Newton matrix (implicit_step.hpp). One
// assembly serves both, so the analysis predicts the matrix the solver uses.
//
// Derivation (docs/stability.md): a link from A to B with d = xB - xA, L = |d|,
// target D and u = d/L gives A the acceleration k (1 - D/L) d. Its derivative in d is
//   M = k [ u u^T + (1 - D/L) (I - u u^T) ]
// (the axial stiffness k along the link plus the geometric term, the link's tension
// k (L - D) / L across it, negative when the link is compressed), so
//   K_AA += M, K_BB += M, K_AB -= M, K_BA -= M
// over the free ends (fixed nodes are not unknowns; a link to one adds only its
// diagonal block). A link of length 0 has no impulse (the engine skips it) and adds
// nothing. Degrees of freedom: (x, y) of free mass i at 2i, 2i + 1.
#pragma once

#include <Eigen/SparseCore>

#include "model.hpp"

namespace soda {

/// Free masses' degrees of freedom: 2 * mass_count.
inline int degrees_of_freedom(const Model& model) { return 2 * model.mass_count; }

/// K at positions (x, y) (arrays of point_count) and wave phase `wave_phase`, in
/// the pattern of stiffness_pattern (explicit zeros where a link has length 0, so
/// that a solver's symbolic factorisation can be reused from step to step).
Eigen::SparseMatrix<double> stiffness_matrix(const Model& model, const double* x, const double* y,
                                             double wave_phase);

/// K of a state.
Eigen::SparseMatrix<double> stiffness_matrix(const Model& model, const State& state);

/// Refills `K` (built by stiffness_matrix for this model) in place, keeping its
/// pattern: no allocation in a stepping loop.
void refill_stiffness(const Model& model, const double* x, const double* y, double wave_phase,
                      Eigen::SparseMatrix<double>& K);

} // namespace soda
