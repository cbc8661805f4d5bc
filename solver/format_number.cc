#include "odomcal/solver/format_number.h"

#include <charconv>

namespace odomcal {

std::string FormatNumber(double value) {
  char text[32];  // the shortest form of any double fits in 24 characters
  const std::to_chars_result end =
      std::to_chars(text, text + sizeof(text), value);
  return std::string(text, end.ptr);
}

}  // namespace odomcal
