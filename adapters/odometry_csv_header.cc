// Each header name is lowercased, split into a base name and the suffix
// after its last '_' (or no suffix), and both are looked up in small tables.
#include "odomcal/adapters/odometry_csv_header.h"

#include "odomcal/solver/angles.h"

#include <cctype>

namespace odomcal {
namespace {

enum class Column { kTime, kX, kY, kYaw };

const char* ColumnName(Column column) {
  switch (column) {
    case Column::kTime:
      return "time";
    case Column::kX:
      return "x";
    case Column::kY:
      return "y";
    case Column::kYaw:
      return "yaw";
  }
  return "";
}

struct NamedColumn {
  Column column;
  std::optional<TimeUnit> time_unit;  // kTime with a suffix
  double factor = 1.0;                // kX, kY: to metres; kYaw: to radians
};

std::optional<Column> BaseColumn(std::string_view base) {
  if (base == "t" || base == "time" || base == "timestamp")
    return Column::kTime;
  if (base == "x") return Column::kX;
  if (base == "y") return Column::kY;
  if (base == "yaw" || base == "theta") return Column::kYaw;
  return std::nullopt;
}

// Applies `suffix` to `named`; false when the suffix does not fit its column.
bool ApplySuffix(std::string_view suffix, NamedColumn* named) {
  switch (named->column) {
    case Column::kTime:
      if (suffix == "s") named->time_unit = TimeUnit::kSeconds;
      if (suffix == "ms") named->time_unit = TimeUnit::kMilliseconds;
      if (suffix == "us") named->time_unit = TimeUnit::kMicroseconds;
      if (suffix == "ns") named->time_unit = TimeUnit::kNanoseconds;
      return named->time_unit.has_value();
    case Column::kX:
    case Column::kY:
      if (suffix == "m") return true;
      if (suffix == "cm") named->factor = 0.01;
      if (suffix == "mm") named->factor = 0.001;
      return suffix == "cm" || suffix == "mm";
    case Column::kYaw:
      if (suffix == "rad") return true;
      if (suffix == "deg") named->factor = kPi / 180.0;
      return suffix == "deg";
  }
  return false;
}

std::string Lowercase(std::string_view name) {
  std::string lower;
  for (const char c : name) {
    lower.push_back(
        static_cast<char>(std::tolower(static_cast<unsigned char>(c))));
  }
  return lower;
}

std::optional<NamedColumn> ParseName(std::string_view name) {
  const std::string lower = Lowercase(name);
  if (const std::optional<Column> column = BaseColumn(lower)) {
    return NamedColumn{*column, std::nullopt, 1.0};
  }
  const size_t underscore = lower.rfind('_');
  if (underscore == std::string::npos) return std::nullopt;
  const std::optional<Column> column =
      BaseColumn(std::string_view(lower).substr(0, underscore));
  if (!column) return std::nullopt;
  NamedColumn named{*column, std::nullopt, 1.0};
  if (!ApplySuffix(std::string_view(lower).substr(underscore + 1), &named)) {
    return std::nullopt;
  }
  return named;
}

std::optional<OdometryCsvColumns> Fail(const std::string& why,
                                       std::string* error) {
  if (error != nullptr) {
    *error = "header " + why + "; accepted: " + kOdometryCsvHeaderGrammar;
  }
  return std::nullopt;
}

enum class Wheel { kLeft, kRight };

// The wheel a name's base ("left" of "left_m") names, if any.
std::optional<Wheel> WheelOf(std::string_view lower) {
  const std::string_view base = lower.substr(0, lower.rfind('_'));
  if (base == "left") return Wheel::kLeft;
  if (base == "right") return Wheel::kRight;
  return std::nullopt;
}

struct NamedWheel {
  Wheel wheel;
  bool ticks = false;
  double to_m = 1.0;
};

// "left_m", "RIGHT_ticks", ...; a missing or unknown suffix is refused.
std::optional<NamedWheel> ParseWheelName(const std::string& lower) {
  const std::optional<Wheel> wheel = WheelOf(lower);
  const size_t underscore = lower.rfind('_');
  if (!wheel || underscore == std::string::npos) return std::nullopt;
  const std::string_view suffix =
      std::string_view(lower).substr(underscore + 1);
  if (suffix == "m") return NamedWheel{*wheel, false, 1.0};
  if (suffix == "cm") return NamedWheel{*wheel, false, 0.01};
  if (suffix == "mm") return NamedWheel{*wheel, false, 0.001};
  if (suffix == "ticks") return NamedWheel{*wheel, true, 1.0};
  return std::nullopt;
}

std::optional<WheelCsvColumns> FailWheel(const std::string& why,
                                         std::string* error) {
  if (error != nullptr) {
    *error =
        "wheel travel header " + why + "; accepted: " + kWheelCsvHeaderGrammar;
  }
  return std::nullopt;
}

}  // namespace

bool LooksLikeWheelCsvHeader(const std::vector<std::string_view>& fields) {
  for (const std::string_view field : fields) {
    if (WheelOf(Lowercase(field))) return true;
  }
  return false;
}

std::optional<WheelCsvColumns> ParseWheelCsvHeader(
    const std::vector<std::string_view>& fields, std::string* error) {
  WheelCsvColumns columns;
  // time, left, right
  int* const index_of[] = {&columns.time, &columns.left, &columns.right};
  std::string* const name_of[] = {
      &columns.time_name, &columns.left_name, &columns.right_name};
  const char* const column_names[] = {"time", "left wheel", "right wheel"};
  bool seen[3] = {false, false, false};
  std::optional<bool> ticks;
  for (size_t i = 0; i < fields.size(); ++i) {
    const std::string name(fields[i]);
    const std::string lower = Lowercase(name);
    int k = 0;
    const std::optional<NamedColumn> time = ParseName(name);
    const std::optional<NamedWheel> wheel = ParseWheelName(lower);
    if (time && time->column == Column::kTime) {
      columns.time_unit = time->time_unit;
    } else if (wheel) {
      k = wheel->wheel == Wheel::kLeft ? 1 : 2;
      if (ticks && *ticks != wheel->ticks) {
        return FailWheel("mixes ticks and distances ('" + name + "')", error);
      }
      ticks = wheel->ticks;
      (k == 1 ? columns.left_to_m : columns.right_to_m) = wheel->to_m;
    } else {
      return FailWheel("column '" + name + "' is not a wheel travel column",
                       error);
    }
    if (seen[k]) {
      return FailWheel("names the " + std::string(column_names[k]) +
                           " column twice ('" + *name_of[k] + "' and '" + name +
                           "')",
                       error);
    }
    seen[k] = true;
    *index_of[k] = static_cast<int>(i);
    *name_of[k] = name;
  }
  for (int k = 0; k < 3; ++k) {
    if (!seen[k]) {
      return FailWheel("has no " + std::string(column_names[k]) + " column",
                       error);
    }
  }
  columns.ticks = ticks.value_or(false);
  return columns;
}

std::optional<OdometryCsvColumns> ParseOdometryCsvHeader(
    const std::vector<std::string_view>& fields, std::string* error) {
  OdometryCsvColumns columns;
  int* const index_of[] = {&columns.time, &columns.x, &columns.y, &columns.yaw};
  std::string* const name_of[] = {
      &columns.time_name, &columns.x_name, &columns.y_name, &columns.yaw_name};
  bool seen[4] = {false, false, false, false};
  for (size_t i = 0; i < fields.size(); ++i) {
    const std::string name(fields[i]);
    const std::optional<NamedColumn> named = ParseName(name);
    if (!named) {
      return Fail("column '" + name + "' is not an odometry column", error);
    }
    const int k = static_cast<int>(named->column);
    if (seen[k]) {
      return Fail("names the " + std::string(ColumnName(named->column)) +
                      " column twice ('" + *name_of[k] + "' and '" + name +
                      "')",
                  error);
    }
    seen[k] = true;
    *index_of[k] = static_cast<int>(i);
    *name_of[k] = name;
    switch (named->column) {
      case Column::kTime:
        columns.time_unit = named->time_unit;
        break;
      case Column::kX:
        columns.x_to_m = named->factor;
        break;
      case Column::kY:
        columns.y_to_m = named->factor;
        break;
      case Column::kYaw:
        columns.yaw_to_rad = named->factor;
        break;
    }
  }
  for (const Column column :
       {Column::kTime, Column::kX, Column::kY, Column::kYaw}) {
    if (!seen[static_cast<int>(column)]) {
      return Fail("has no " + std::string(ColumnName(column)) + " column",
                  error);
    }
  }
  return columns;
}

}  // namespace odomcal
