#include "odomcal/solver/format_number.h"

#include <algorithm>
#include <charconv>
#include <cstdio>
#include <cstdlib>

namespace odomcal {

std::string FormatNumber(double value) {
  char text[32];  // the shortest form of any double fits in 24 characters
  const std::to_chars_result end =
      std::to_chars(text, text + sizeof(text), value);
  return std::string(text, end.ptr);
}

std::string FormatRounded(double value, int significant_digits) {
  char text[40];
  std::snprintf(
      text, sizeof(text), "%.*g", std::clamp(significant_digits, 1, 17), value);
  return FormatNumber(std::strtod(text, nullptr));
}

std::string FormatPrintf(const char* printf_format, double value) {
  char text[128];
  std::snprintf(text, sizeof(text), printf_format, value);
  return text;
}

}  // namespace odomcal
