#include "stiffness.hpp"

#include <cmath>
#include <vector>

#include "physics_rules.hpp"

namespace soda {

namespace {

/// The 2x2 block M of one link (see the header), row-major m[0..3]; zero for a
/// link of length 0.
void link_block(const Model& m, int i, const double* x, const double* y, double wave_phase, double* block) {
  const int a = m.link_a[i];
  const int b = m.link_b[i];
  const double dx = x[b] - x[a];
  const double dy = y[b] - y[a];
  const double length = std::sqrt(dx * dx + dy * dy);
  if (length == 0.0) {
    block[0] = block[1] = block[2] = block[3] = 0.0;
    return;
  }
  const double ux = dx / length;
  const double uy = dy / length;
  const double k = m.springyness;
  const double tension = 1.0 - rules::link_target_length(m, i, wave_phase, SineJitter{}) / length; // (L - D) / L; exact sine: a jittered ulp moves no eigenvalue that matters
  // k [u u^T + tension (I - u u^T)] = k [tension I + (1 - tension) u u^T]
  const double axial = k * (1.0 - tension);
  block[0] = k * tension + axial * ux * ux;
  block[1] = axial * ux * uy;
  block[2] = block[1];
  block[3] = k * tension + axial * uy * uy;
}

/// Calls add(row, col, value) for every entry of every link's blocks (in link
/// order, blocks AA, BB, AB, BA), zeros included.
template <class Add>
void for_each_entry(const Model& m, const double* x, const double* y, double wave_phase, Add&& add) {
  double block[4];
  for (int i = 0; i < m.link_count(); ++i) {
    const int a = m.link_a[i];
    const int b = m.link_b[i];
    const bool free_a = m.is_mass(a);
    const bool free_b = m.is_mass(b);
    if (!free_a && !free_b) continue;
    link_block(m, i, x, y, wave_phase, block);
    auto put = [&](int p, int q, double sign) {
      for (int r = 0; r < 2; ++r)
        for (int c = 0; c < 2; ++c) add(2 * p + r, 2 * q + c, sign * block[2 * r + c]);
    };
    if (free_a) put(a, a, 1.0);
    if (free_b) put(b, b, 1.0);
    if (free_a && free_b) {
      put(a, b, -1.0);
      put(b, a, -1.0);
    }
  }
}

} // namespace

Eigen::SparseMatrix<double> stiffness_matrix(const Model& model, const double* x, const double* y,
                                             double wave_phase) {
  const int n = degrees_of_freedom(model);
  std::vector<Eigen::Triplet<double>> entries;
  entries.reserve(static_cast<std::size_t>(model.link_count()) * 16);
  // Every diagonal entry is in the pattern, so K + s I keeps K's pattern.
  for (int d = 0; d < n; ++d) entries.emplace_back(d, d, 0.0);
  for_each_entry(model, x, y, wave_phase, [&](int r, int c, double v) { entries.emplace_back(r, c, v); });
  Eigen::SparseMatrix<double> K(n, n);
  K.setFromTriplets(entries.begin(), entries.end()); // duplicates are summed
  return K;
}

Eigen::SparseMatrix<double> stiffness_matrix(const Model& model, const State& state) {
  require_state_size(state, model.point_count, "stiffness_matrix");
  return stiffness_matrix(model, state.x.data(), state.y.data(), state.wave_phase);
}

void refill_stiffness(const Model& model, const double* x, const double* y, double wave_phase,
                      Eigen::SparseMatrix<double>& K) {
  for (int k = 0; k < K.outerSize(); ++k)
    for (Eigen::SparseMatrix<double>::InnerIterator it(K, k); it; ++it) it.valueRef() = 0.0;
  for_each_entry(model, x, y, wave_phase, [&](int r, int c, double v) { K.coeffRef(r, c) += v; });
}

} // namespace soda
