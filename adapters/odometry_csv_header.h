// The header line of an odometry CSV: which column holds what, in which unit.
//
// Grammar: exactly four comma-separated names, in any order, compared
// case-insensitively, each a base name with an optional unit suffix:
//   time   t | time | timestamp   suffix _s | _ms | _us | _ns
//   x, y   x | y                  suffix _m | _cm | _mm
//   yaw    yaw | theta            suffix _rad | _deg
// e.g. "timestamp,x,y,yaw", "time_ns,x_mm,y_mm,yaw_deg", "Yaw,T,X,Y".
// Without a suffix: the time unit the caller passes (the time unit flag),
// metres and radians. Every name must be known and each of the four columns
// named once; anything else is refused with the accepted names.
#pragma once

#include "odomcal/adapters/timestamp.h"

#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace odomcal {

// Accepted names, for messages and documentation.
inline constexpr char kOdometryCsvHeaderGrammar[] =
    "t|time|timestamp[_s|_ms|_us|_ns], x[_m|_cm|_mm], y[_m|_cm|_mm], "
    "yaw|theta[_rad|_deg] (any order, any case)";

struct OdometryCsvColumns {
  // Field index of each column.
  int time = 0;
  int x = 1;
  int y = 2;
  int yaw = 3;
  // The names as written in the header, for messages.
  std::string time_name = "timestamp";
  std::string x_name = "x";
  std::string y_name = "y";
  std::string yaw_name = "yaw";
  // Unit of the time column when its name has a suffix.
  std::optional<TimeUnit> time_unit;
  // Factors to metres and radians.
  double x_to_m = 1.0;
  double y_to_m = 1.0;
  double yaw_to_rad = 1.0;
};

// Columns of a header line (its fields, already split and trimmed). Returns
// std::nullopt and sets *error (when not null) to a one-line reason that
// names the offending name and lists kOdometryCsvHeaderGrammar: an unknown
// name, a column named twice, a missing column.
std::optional<OdometryCsvColumns> ParseOdometryCsvHeader(
    const std::vector<std::string_view>& fields, std::string* error);

}  // namespace odomcal
