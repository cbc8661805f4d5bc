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

// The header of a wheel-travel CSV (wheel_travel.h): three names, any order,
// any case: the time as above, and the cumulative travel of each wheel with
// a unit suffix that is required (a bare "left" could be metres or ticks):
//   left, right   suffix _m | _cm | _mm | _ticks (both the same kind)
// e.g. "timestamp,left_m,right_m", "time_ns,left_ticks,right_ticks".
inline constexpr char kWheelCsvHeaderGrammar[] =
    "t|time|timestamp[_s|_ms|_us|_ns], left_m|left_cm|left_mm|left_ticks, "
    "right_m|right_cm|right_mm|right_ticks (any order, any case; both wheels "
    "in distance or both in ticks)";

struct WheelCsvColumns {
  int time = 0;
  int left = 1;
  int right = 2;
  std::string time_name = "timestamp";
  std::string left_name = "left_m";
  std::string right_name = "right_m";
  std::optional<TimeUnit> time_unit;
  // Encoder counts (integers, converted with the ticks per metre the caller
  // is given) instead of distances.
  bool ticks = false;
  // Distances: factor to metres (both wheels use the same unit or not, each
  // its own factor).
  double left_to_m = 1.0;
  double right_to_m = 1.0;
};

// True when `fields` look like a wheel-travel header rather than an odometry
// pose header: one of them names a left or right wheel column (with any or
// no suffix), so that its errors list the wheel grammar.
bool LooksLikeWheelCsvHeader(const std::vector<std::string_view>& fields);

// Columns of a wheel-travel header; as ParseOdometryCsvHeader, the error
// lists kWheelCsvHeaderGrammar. Also refused: one wheel in ticks and the other
// in a distance.
std::optional<WheelCsvColumns> ParseWheelCsvHeader(
    const std::vector<std::string_view>& fields, std::string* error);

}  // namespace odomcal
