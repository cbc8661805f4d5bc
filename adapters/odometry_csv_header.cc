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

std::optional<NamedColumn> ParseName(std::string_view name) {
  std::string lower;
  for (const char c : name) {
    lower.push_back(
        static_cast<char>(std::tolower(static_cast<unsigned char>(c))));
  }
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

}  // namespace

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
