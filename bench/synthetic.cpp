#include "bench/synthetic.hpp"

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

namespace sodaevo::bench {

soda::ModelDef synthetic_creature(int links) {
  constexpr double kSpacing = 25.0;
  links = std::max(links, 1);
  // Rows grow with the size so that big creatures are blocks, small ones strips.
  const int rows = std::clamp(static_cast<int>(std::lround(std::sqrt(static_cast<double>(links)) / 4.0)), 2, 64);
  const int cols = links / (4 * (rows - 1)) + 3;
  auto id = [rows](int c, int r) { return c * rows + r; };

  std::vector<soda::LinkDef> all;
  int muscle_index = 0;
  for (int c = 0; c < cols && static_cast<int>(all.size()) < links; ++c) {
    for (int r = 0; r < rows; ++r) {
      if (r + 1 < rows) all.push_back({soda::LinkKind::Spring, id(c, r), id(c, r + 1), kSpacing, 0, 0});
      if (c + 1 < cols) all.push_back({soda::LinkKind::Spring, id(c, r), id(c + 1, r), kSpacing, 0, 0});
      if (c + 1 < cols && r + 1 < rows) {
        const double diagonal = kSpacing * std::sqrt(2.0);
        all.push_back({soda::LinkKind::Muscle, id(c, r), id(c + 1, r + 1), diagonal, 0.5,
                       static_cast<double>((muscle_index++ % 8) * 32) / 255.0});
        all.push_back({soda::LinkKind::Spring, id(c + 1, r), id(c, r + 1), diagonal, 0, 0});
      }
    }
  }
  all.resize(std::min(all.size(), static_cast<std::size_t>(links)));

  soda::ModelDef def;
  def.name = std::to_string(links);
  def.name.insert(0, "synthetic ");
  def.name += " links";
  def.wave = {0.5, 0.0, 2.5 / 255.0};
  def.environment = {0.3, 0.05, 0.2};
  std::vector<int> new_index(static_cast<std::size_t>(rows * cols), -1);
  for (soda::LinkDef& l : all) {
    for (int* end : {&l.a, &l.b}) {
      if (new_index[*end] < 0) {
        new_index[*end] = static_cast<int>(def.nodes.size());
        const int c = *end / rows, r = *end % rows;
        std::string id = std::to_string(def.nodes.size());
        id.insert(0, 1, 'm'); // (not "m" + ...: GCC 12 warns falsely on that)
        def.nodes.push_back({id, false, 100.0 + c * kSpacing, 0.5 + r * kSpacing, 0.0, 0.0});
      }
      *end = new_index[*end];
    }
  }
  def.links = std::move(all);
  def.width = static_cast<int>(cols * kSpacing + 200.0);
  def.height = static_cast<int>(rows * kSpacing + 400.0);
  return def;
}

} // namespace sodaevo::bench
