#include "formats/trace_csv.hpp"

#include <string>

#include "core/number_text.hpp"

namespace soda {

TraceCsv::TraceCsv(std::ostream& out, const Model& model) : out_(out), mass_count_(model.mass_count) {
  out_ << "frame,wave_phase,wave_mode";
  for (int i = 0; i < mass_count_; ++i) {
    out_ << ",x" << i << ",y" << i << ",vx" << i << ",vy" << i;
  }
  out_ << '\n';
}

void TraceCsv::write_row(const State& s) {
  std::string row = std::to_string(s.frame);
  row += ',';
  row += format_double_plain(s.wave_phase);
  row += ',';
  row += std::to_string(static_cast<int>(s.wave_mode));
  for (int i = 0; i < mass_count_; ++i) {
    for (double v : {s.x[i], s.y[i], s.vx[i], s.vy[i]}) {
      row += ',';
      row += format_double_plain(v);
    }
  }
  row += '\n';
  out_ << row;
}

} // namespace soda
