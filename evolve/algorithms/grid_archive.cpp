#include "grid_archive.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace sodaevo {

Judgement judge(const RunningEstimate* elite, const RunningEstimate& challenger, const ResamplePlan& plan,
                bool confirmed) {
  const long long cap = plan.cap;
  if (elite == nullptr) return {Verdict::Enter, 0};
  if (challenger.n < elite->n && challenger.n < cap) {
    if (!(challenger.mean > elite->mean)) return {Verdict::Reject, 0};
    return {Verdict::SampleChallenger, std::min(elite->n, cap) - challenger.n};
  }
  if (elite->n < challenger.n && elite->n < cap) {
    return {Verdict::SampleElite, std::min(challenger.n, cap) - elite->n};
  }
  if (!(challenger.mean > elite->mean)) return {Verdict::Reject, 0};
  if (!confirmed && challenger.n < cap && elite->n < cap) {
    return {Verdict::SampleBoth, std::min(plan.step, cap - std::max(challenger.n, elite->n))};
  }
  return {Verdict::Replace, 0};
}

GridArchive::GridArchive(std::vector<GridAxis> axes) : axes_(std::move(axes)) {
  for (const GridAxis& a : axes_) {
    if (a.bins < 1 || !(a.lo < a.hi)) throw std::invalid_argument("GridArchive: an axis needs bins >= 1 and lo < hi");
    cells_ *= static_cast<std::size_t>(a.bins);
  }
}

int GridArchive::bin_of(std::size_t axis, double value) const {
  const GridAxis& a = axes_.at(axis);
  const double t = (value - a.lo) / (a.hi - a.lo) * a.bins;
  if (!(t >= 0.0)) return 0; // below the range (or NaN): the first bin
  if (t >= a.bins) return a.bins - 1;
  return std::min(static_cast<int>(t), a.bins - 1);
}

std::size_t GridArchive::cell_of(const std::vector<double>& values) const {
  if (values.size() != axes_.size()) throw std::invalid_argument("GridArchive::cell_of: one value per axis");
  std::size_t cell = 0;
  for (std::size_t a = 0; a < axes_.size(); ++a) {
    cell = cell * static_cast<std::size_t>(axes_[a].bins) + static_cast<std::size_t>(bin_of(a, values[a]));
  }
  return cell;
}

std::size_t GridArchive::cell_of(const Behaviour& behaviour) const {
  std::vector<double> values;
  for (const GridAxis& a : axes_) values.push_back(behaviour[static_cast<std::size_t>(a.descriptor)]);
  return cell_of(values);
}

std::vector<double> GridArchive::axis_values(const std::vector<double>& descriptors) const {
  std::vector<double> values;
  for (const GridAxis& a : axes_) {
    const auto d = static_cast<std::size_t>(a.descriptor);
    if (d >= descriptors.size()) throw std::invalid_argument("GridArchive::axis_values: descriptor missing");
    values.push_back(descriptors[d]);
  }
  return values;
}

std::vector<int> GridArchive::coordinates(std::size_t cell) const {
  std::vector<int> c(axes_.size());
  for (std::size_t a = axes_.size(); a-- > 0;) {
    const auto bins = static_cast<std::size_t>(axes_[a].bins);
    c[a] = static_cast<int>(cell % bins);
    cell /= bins;
  }
  return c;
}

const ArchiveEntry* GridArchive::elite(std::size_t cell) const {
  const auto it = elites_.find(cell);
  return it == elites_.end() ? nullptr : &it->second;
}

ArchiveEntry* GridArchive::elite(std::size_t cell) {
  const auto it = elites_.find(cell);
  return it == elites_.end() ? nullptr : &it->second;
}

void GridArchive::place(std::size_t cell, ArchiveEntry entry) {
  if (cell >= cells_) throw std::out_of_range("GridArchive::place: no such cell");
  elites_[cell] = std::move(entry);
}

QdMetrics GridArchive::metrics(double qd_offset) const {
  QdMetrics m;
  m.cells = cells_;
  m.filled = elites_.size();
  m.coverage = static_cast<double>(m.filled) / static_cast<double>(m.cells);
  if (elites_.empty()) return m;
  double sum = 0.0;
  m.best = -INFINITY;
  for (const auto& [cell, e] : elites_) {
    m.qd_score += std::max(0.0, e.fitness.mean - qd_offset);
    sum += e.fitness.mean;
    m.best = std::max(m.best, e.fitness.mean);
  }
  m.normalized_qd_score = m.qd_score / static_cast<double>(m.cells);
  m.mean = sum / static_cast<double>(m.filled);
  return m;
}

} // namespace sodaevo
