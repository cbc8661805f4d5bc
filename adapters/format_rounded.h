// Computed numbers in messages, rounded: "peak 0.369", not the shortest
// round-trip text FormatNumber (solver/format_number.h) gives, which for a
// computed double is often 17 digits ("0.36927100577991273"). Values the
// user gave keep FormatNumber, so that a message quotes them exactly.
#pragma once

#include <string>

namespace odomcal {

// `value` rounded to `significant_digits` (>= 1), written as FormatNumber
// writes the rounded double: 0.36927 -> "0.369", 1234.5 -> "1230",
// 0.030000000000000002 -> "0.03", 2.5e-7 -> "2.5e-07", "nan", "inf".
std::string FormatRounded(double value, int significant_digits = 3);

}  // namespace odomcal
