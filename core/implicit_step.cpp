#include "implicit_step.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include <Eigen/SparseCholesky>

#include "stiffness.hpp"

namespace soda {

struct ImplicitSolver::Linear {
  Eigen::SparseMatrix<double> K, J;                     ///< J = dt h K + alpha I, K's pattern
  std::vector<Eigen::Index> diagonal;                    ///< index of each diagonal entry in J's values
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> ldlt; ///< symbolic analysis done once
  Eigen::VectorXd residual, update;
};

ImplicitSolver::ImplicitSolver(const Model& model, double dt, double drag, bool midpoint, Acceleration acceleration)
    : model_(model),
      dt_(dt),
      h_(midpoint ? dt / 2.0 : dt),
      alpha_(midpoint ? 2.0 + drag * dt : 1.0 + drag * dt),
      beta_(midpoint ? 2.0 : 1.0),
      acceleration_(std::move(acceleration)),
      linear_(std::make_unique<Linear>()) {
  const auto points = static_cast<std::size_t>(model.point_count);
  w_.assign(2 * static_cast<std::size_t>(model.mass_count), 0.0);
  ax_.assign(points, 0.0);
  ay_.assign(points, 0.0);
  if (model.mass_count == 0) return;
  Linear& l = *linear_;
  l.K = stiffness_matrix(model, model.x0.data(), model.y0.data(), model.wave_phase0);
  l.J = l.K;
  for (Eigen::Index c = 0; c < l.J.outerSize(); ++c) {
    for (Eigen::SparseMatrix<double>::InnerIterator it(l.J, c); it; ++it) {
      if (it.row() == it.col()) l.diagonal.push_back(&it.valueRef() - l.J.valuePtr());
    }
  }
  l.ldlt.analyzePattern(l.J);
}

ImplicitSolver::~ImplicitSolver() = default;

bool ImplicitSolver::step(const double* x, const double* y, const double* vx, const double* vy, double phase_eval,
                          double* x1, double* y1, double* vx1, double* vy1, std::string& why) {
  const Model& m = model_;
  const int n = m.mass_count;
  std::copy(x, x + m.point_count, x1); // fixed points keep their place
  std::copy(y, y + m.point_count, y1);
  std::copy(vx, vx + m.point_count, vx1);
  std::copy(vy, vy + m.point_count, vy1);
  if (n == 0) return true;
  Linear& l = *linear_;
  for (int i = 0; i < n; ++i) { // start from the current velocity
    w_[2 * i] = vx[i];
    w_[2 * i + 1] = vy[i];
  }
  l.residual.resize(2 * n);
  char text[160];
  for (int iteration = 1; iteration <= kMaxNewtonIterations; ++iteration) {
    for (int i = 0; i < n; ++i) { // x1 holds the evaluation point x + h w
      x1[i] = x[i] + h_ * w_[2 * i];
      y1[i] = y[i] + h_ * w_[2 * i + 1];
    }
    acceleration_(x1, y1, phase_eval, ax_.data(), ay_.data());
    for (int i = 0; i < n; ++i) {
      l.residual[2 * i] = -(alpha_ * w_[2 * i] - beta_ * vx[i] - dt_ * ax_[i]);
      l.residual[2 * i + 1] = -(alpha_ * w_[2 * i + 1] - beta_ * vy[i] - dt_ * ay_[i]);
    }
    refill_stiffness(m, x1, y1, phase_eval, l.K);
    const double scale = dt_ * h_;
    const Eigen::Index nonzeros = l.K.nonZeros();
    for (Eigen::Index k = 0; k < nonzeros; ++k) l.J.valuePtr()[k] = scale * l.K.valuePtr()[k];
    for (Eigen::Index k : l.diagonal) l.J.valuePtr()[k] += alpha_;
    l.ldlt.factorize(l.J);
    const Eigen::VectorXd& d = l.ldlt.vectorD();
    const double largest = d.cwiseAbs().maxCoeff();
    if (l.ldlt.info() != Eigen::Success || !std::isfinite(largest) || d.cwiseAbs().minCoeff() <= 1e-13 * largest) {
      std::snprintf(text, sizeof text, "singular Newton matrix (pivots %.3g .. %.3g) in iteration %d",
                    d.size() ? d.cwiseAbs().minCoeff() : 0.0, largest, iteration);
      why = text;
      return false;
    }
    l.update = l.ldlt.solve(l.residual);
    if (!l.update.allFinite()) {
      std::snprintf(text, sizeof text, "non-finite Newton update in iteration %d", iteration);
      why = text;
      return false;
    }
    double step_size = 0.0, speed = 0.0;
    for (int k = 0; k < 2 * n; ++k) {
      w_[static_cast<std::size_t>(k)] += l.update[k];
      step_size = std::max(step_size, std::fabs(l.update[k]));
      speed = std::max(speed, std::fabs(w_[static_cast<std::size_t>(k)]));
    }
    if (!std::isfinite(speed)) {
      std::snprintf(text, sizeof text, "non-finite Newton iterate in iteration %d", iteration);
      why = text;
      return false;
    }
    if (step_size <= kNewtonTolerance * (speed + 1.0)) {
      for (int i = 0; i < n; ++i) {
        const double wx = w_[2 * i], wy = w_[2 * i + 1];
        x1[i] = x[i] + dt_ * wx;
        y1[i] = y[i] + dt_ * wy;
        vx1[i] = beta_ == 1.0 ? wx : 2.0 * wx - vx[i]; // midpoint: w is the mean velocity
        vy1[i] = beta_ == 1.0 ? wy : 2.0 * wy - vy[i];
      }
      return true;
    }
    if (iteration == kMaxNewtonIterations) {
      std::snprintf(text, sizeof text, "Newton did not converge in %d iterations (last update %.3g px/frame)",
                    kMaxNewtonIterations, step_size);
      why = text;
    }
  }
  return false;
}

} // namespace soda
