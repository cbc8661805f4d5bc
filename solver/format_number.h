// Numbers in messages: the shortest text that reads back as the same double
// ("-1", "0.25", "1e+300", "nan"), not std::to_string's fixed six decimals
// ("-1.000000", and 309 digits for the largest double).
#pragma once

#include <string>

namespace odomcal {

std::string FormatNumber(double value);

}  // namespace odomcal
