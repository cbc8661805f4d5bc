#include "odomcal/adapters/format_rounded.h"

#include "odomcal/solver/format_number.h"

#include <algorithm>
#include <cstdio>
#include <cstdlib>

namespace odomcal {

std::string FormatRounded(double value, int significant_digits) {
  char text[40];
  std::snprintf(
      text, sizeof(text), "%.*g", std::clamp(significant_digits, 1, 17), value);
  return FormatNumber(std::strtod(text, nullptr));
}

}  // namespace odomcal
