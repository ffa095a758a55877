// Fixed-point text for tables and reports ("%.*f"): one definition for the
// benchmark tables and the run report.
#pragma once

#include <cstdio>
#include <string>

namespace sodaevo::charts {

inline std::string fixed(double v, int digits) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.*f", digits, v);
  return buf;
}

} // namespace sodaevo::charts
