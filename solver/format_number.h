// Numbers in messages: the shortest text that reads back as the same double
// ("-1", "0.25", "1e+300", "nan"), not std::to_string's fixed six decimals
// ("-1.000000", and 309 digits for the largest double).
//
// Values the user gave are quoted exactly with FormatNumber. Computed values
// are rounded first with FormatRounded: "peak 0.369", not the 17 digits
// ("0.36927100577991273") the shortest round-trip text of a computed double
// often needs.
#pragma once

#include <string>

namespace odomcal {

std::string FormatNumber(double value);

// `value` rounded to `significant_digits` (>= 1), written as FormatNumber
// writes the rounded double: 0.36927 -> "0.369", 1234.5 -> "1230",
// 0.030000000000000002 -> "0.03", 2.5e-7 -> "2.5e-07", "nan", "inf".
std::string FormatRounded(double value, int significant_digits = 3);

// `value` written by std::snprintf with `printf_format`, which takes exactly
// one double ("%.3f", "%10.4f deg"); texts past 127 characters are cut.
std::string FormatPrintf(const char* printf_format, double value);

}  // namespace odomcal
