// TUM and odometry CSV readers and writers. A LineReader yields the data
// lines of a file (skipping blank lines and '#' comments) with their 1-based
// numbers; each line is split into fields (on commas when it has any,
// otherwise on runs of blanks), the timestamp field goes through the exact
// ParseTimestampNs and the others through std::from_chars, which is
// locale-independent unlike strtod. Each check throws a FormatError prefixed
// with "path:line: ". An odometry CSV header becomes OdometryCsvColumns
// (odometry_csv_header.h): field indices and factors to s, m and rad applied
// while reading; ReadOdometry opens the file twice under kAuto, once to see
// the first data line's field count. Writers format timestamps from the integer
// nanoseconds, never through a double, and values with %.17g so that a
// written file reads back to the same doubles.
#include "odomcal/adapters/trajectory_io.h"

#include "odomcal/adapters/input_plausibility.h"
#include "odomcal/adapters/odometry_csv_header.h"
#include "odomcal/adapters/text_reader.h"
#include "odomcal/adapters/wheel_travel.h"
#include "odomcal/solver/planarity_check.h"

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <string_view>
#include <system_error>
#include <vector>

namespace odomcal {
namespace {

constexpr double kMaxPoseQuaternionNormDeviation = 1e-2;

constexpr const char* kTumColumns[] = {
    "timestamp", "tx", "ty", "tz", "qx", "qy", "qz", "qw"};
constexpr const char* kTumColumnList = "timestamp tx ty tz qx qy qz qw";
constexpr const char* kCsvColumnList = "timestamp,x,y,yaw";
constexpr const char* kWheelColumnList = "timestamp,left_m,right_m";

std::string SystemReason() {
  return errno != 0 ? std::string(": ") + std::strerror(errno) : std::string();
}

[[noreturn]] void ThrowAt(const std::string& path,
                          int line_number,
                          const std::string& what) {
  throw FormatError(path + ":" + std::to_string(line_number) + ": " + what);
}

// Data lines of a text file, with their 1-based line numbers.
class LineReader {
 public:
  explicit LineReader(const std::string& path) : path_(path) {
    std::error_code ignored;
    if (std::filesystem::is_directory(path, ignored)) {
      throw FormatError(path + ": cannot open for reading: is a directory");
    }
    errno = 0;
    stream_.open(path);
    if (!stream_.is_open()) {
      throw FormatError(path + ": cannot open for reading" + SystemReason());
    }
  }

  // Next line that is neither blank nor a '#' comment, without a trailing
  // '\r'. Returns false at the end of the file.
  bool Next(std::string* line) {
    while (std::getline(stream_, *line)) {
      ++line_number_;
      if (line_number_ == 1) StripUtf8Bom(line);
      if (!line->empty() && line->back() == '\r') line->pop_back();
      const size_t first = line->find_first_not_of(" \t");
      if (first == std::string::npos || (*line)[first] == '#') continue;
      return true;
    }
    if (stream_.bad()) {
      throw FormatError(path_ + ":" + std::to_string(line_number_ + 1) +
                        ": read error");
    }
    return false;
  }

  int line_number() const { return line_number_; }
  const std::string& path() const { return path_; }

  [[noreturn]] void Fail(const std::string& what) const {
    ThrowAt(path_, line_number_, what);
  }

  [[noreturn]] void FailNoData() const {
    throw FormatError(path_ + ": no data lines (" +
                      std::to_string(line_number_) +
                      " lines, all blank or '#' comments)");
  }

 private:
  std::string path_;
  std::ifstream stream_;
  int line_number_ = 0;
};

std::string_view Trim(std::string_view text) {
  const size_t first = text.find_first_not_of(" \t");
  if (first == std::string_view::npos) return {};
  const size_t last = text.find_last_not_of(" \t");
  return text.substr(first, last - first + 1);
}

// Comma-separated when the line has a comma (fields trimmed, empty fields
// kept so that they are reported), otherwise blank-separated.
std::vector<std::string_view> SplitFields(std::string_view line) {
  std::vector<std::string_view> fields;
  if (line.find(',') != std::string_view::npos) {
    size_t begin = 0;
    while (true) {
      const size_t comma = line.find(',', begin);
      fields.push_back(Trim(line.substr(begin, comma - begin)));
      if (comma == std::string_view::npos) break;
      begin = comma + 1;
    }
    return fields;
  }
  size_t pos = 0;
  while (pos < line.size()) {
    const size_t begin = line.find_first_not_of(" \t", pos);
    if (begin == std::string_view::npos) break;
    size_t end = line.find_first_of(" \t", begin);
    if (end == std::string_view::npos) end = line.size();
    fields.push_back(line.substr(begin, end - begin));
    pos = end;
  }
  return fields;
}

// True when the field starts like a number; used to recognise a header.
bool LooksNumeric(std::string_view field) {
  return !field.empty() &&
         (std::isdigit(static_cast<unsigned char>(field[0])) ||
          field[0] == '-' || field[0] == '+' || field[0] == '.');
}

// `format_hint` (may be empty) is appended on the first data line, where a
// wrong count means a wrong format rather than a broken line.
void CheckFieldCount(const LineReader& reader,
                     const std::vector<std::string_view>& fields,
                     size_t expected,
                     const std::string& column_list,
                     bool first_data_line,
                     const std::string& format_hint) {
  if (fields.size() != expected) {
    reader.Fail("expected " + std::to_string(expected) + " fields (" +
                column_list + "), got " + std::to_string(fields.size()) +
                (first_data_line ? format_hint : std::string()));
  }
}

// The field as std::from_chars reads it: without a leading '+', which it
// does not accept (a sign after the '+' stays, so "+-1" is still refused).
std::string_view WithoutLeadingPlus(std::string_view field) {
  if (field.size() > 1 && field[0] == '+' && field[1] != '-' &&
      field[1] != '+') {
    field.remove_prefix(1);
  }
  return field;
}

double ParseValue(const LineReader& reader,
                  std::string_view field,
                  const std::string& column) {
  const std::string name = "column '" + column + "'";
  if (field.empty()) reader.Fail(name + " is empty");
  const std::string_view digits = WithoutLeadingPlus(field);
  double value = 0.0;
  const auto [end, ec] =
      std::from_chars(digits.data(), digits.data() + digits.size(), value);
  if (ec == std::errc::result_out_of_range) {
    reader.Fail(name + " is out of the double range: '" + std::string(field) +
                "'");
  }
  if (ec != std::errc() || end != digits.data() + digits.size()) {
    reader.Fail(name + " is not a number: '" + std::string(field) + "'");
  }
  if (!std::isfinite(value)) {
    reader.Fail(name + " is not finite (NaN or Inf): '" + std::string(field) +
                "'");
  }
  return value;
}

int64_t ParseStamp(const LineReader& reader,
                   std::string_view field,
                   TimeUnit unit,
                   const std::string& column = "timestamp") {
  std::string error;
  const std::optional<int64_t> stamp_ns = ParseTimestampNs(field, unit, &error);
  if (!stamp_ns) reader.Fail("column '" + column + "': " + error);
  return *stamp_ns;
}

int64_t ParseTicks(const LineReader& reader,
                   std::string_view field,
                   const std::string& column) {
  const std::string name = "column '" + column + "'";
  if (field.empty()) reader.Fail(name + " is empty");
  const std::string_view digits = WithoutLeadingPlus(field);
  int64_t value = 0;
  const auto [end, ec] =
      std::from_chars(digits.data(), digits.data() + digits.size(), value);
  if (ec == std::errc::result_out_of_range) {
    reader.Fail(name + " is out of the 64-bit integer range: '" +
                std::string(field) + "'");
  }
  if (ec != std::errc() || end != digits.data() + digits.size()) {
    reader.Fail(name + " is not an integer tick count: '" + std::string(field) +
                "'");
  }
  return value;
}

// Refuses duplicate and decreasing timestamps, naming both lines.
class IncreasingStamps {
 public:
  void Check(const LineReader& reader,
             int64_t stamp_ns,
             std::string_view text) {
    if (previous_line_ > 0 && stamp_ns <= previous_ns_) {
      reader.Fail(std::string(stamp_ns == previous_ns_
                                  ? "duplicate timestamp "
                                  : "timestamp not increasing: ") +
                  std::string(text) + " after " + previous_text_ + " on line " +
                  std::to_string(previous_line_));
    }
    previous_ns_ = stamp_ns;
    previous_text_ = std::string(text);
    previous_line_ = reader.line_number();
  }

 private:
  int64_t previous_ns_ = 0;
  std::string previous_text_;
  int previous_line_ = 0;
};

std::string FormatValue(double value) {
  char buffer[32];
  std::snprintf(buffer, sizeof(buffer), "%.17g", value);
  return buffer;
}

std::ofstream OpenForWriting(const std::string& path) {
  errno = 0;
  std::ofstream stream(path);
  if (!stream.is_open()) {
    throw FormatError(path + ": cannot open for writing" + SystemReason());
  }
  return stream;
}

void FinishWriting(std::ofstream& stream, const std::string& path) {
  errno = 0;
  stream.close();
  if (stream.fail()) {
    throw FormatError(path + ": write failed" + SystemReason());
  }
}

std::string LowercaseExtension(const std::string& path) {
  std::string extension = std::filesystem::path(path).extension().string();
  std::transform(
      extension.begin(), extension.end(), extension.begin(), [](char c) {
        return static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
      });
  return extension;
}

// The format the first data line (after an optional header) shows: 4
// fields -> CSV, 8 -> TUM, else std::nullopt with *num_fields and *line set.
std::optional<OdometryFormat> FormatByContent(const std::string& path,
                                              size_t* num_fields,
                                              int* line_number) {
  LineReader reader(path);
  std::string line;
  bool first = true;
  while (reader.Next(&line)) {
    const std::vector<std::string_view> fields = SplitFields(line);
    if (first && !fields.empty() && !LooksNumeric(fields[0])) {
      if (LooksLikeWheelCsvHeader(fields)) return OdometryFormat::kCsv;
      first = false;
      continue;  // a header
    }
    if (fields.size() == 4) return OdometryFormat::kCsv;
    if (fields.size() == 8) return OdometryFormat::kTum;
    *num_fields = fields.size();
    *line_number = reader.line_number();
    return std::nullopt;
  }
  reader.FailNoData();
}

const char* FormatName(OdometryFormat format) {
  return format == OdometryFormat::kCsv ? "csv" : "tum";
}

Trajectory ReadTum(const std::string& path,
                   TimeUnit unit,
                   const std::string& format_hint) {
  Trajectory trajectory;
  trajectory.source = path;
  trajectory.planar = false;
  LineReader reader(path);
  IncreasingStamps increasing;
  std::string line;
  while (reader.Next(&line)) {
    const std::vector<std::string_view> fields = SplitFields(line);
    CheckFieldCount(reader,
                    fields,
                    8,
                    kTumColumnList,
                    trajectory.poses.empty(),
                    format_hint);
    StampedPose pose;
    pose.stamp_ns = ParseStamp(reader, fields[0], unit);
    double values[8];
    for (int i = 1; i < 8; ++i) {
      values[i] = ParseValue(reader, fields[i], kTumColumns[i]);
    }
    // File order qx qy qz qw; Eigen's constructor takes w, x, y, z.
    const Eigen::Quaterniond rotation(
        values[7], values[4], values[5], values[6]);
    const double norm = rotation.norm();
    if (std::abs(norm - 1.0) > kMaxPoseQuaternionNormDeviation) {
      reader.Fail("quaternion (qx qy qz qw) has norm " + FormatValue(norm) +
                  ", more than " +
                  FormatValue(kMaxPoseQuaternionNormDeviation) +
                  " away from 1");
    }
    pose.world_from_sensor.rotation = rotation.normalized();
    pose.world_from_sensor.translation =
        Eigen::Vector3d(values[1], values[2], values[3]);
    increasing.Check(reader, pose.stamp_ns, fields[0]);
    trajectory.poses.push_back(pose);
  }
  if (trajectory.poses.empty()) reader.FailNoData();
  trajectory.time_unit = unit;
  return trajectory;
}

// The unit of the time column: the header's suffix, else `unit`. A suffix
// that contradicts a time unit the user gave is an error naming both.
TimeUnit TimeColumnUnit(const LineReader& reader,
                        const OdometryCsvColumns& columns,
                        TimeUnit unit,
                        bool unit_given) {
  if (!columns.time_unit) return unit;
  if (unit_given && *columns.time_unit != unit) {
    reader.Fail("header column '" + columns.time_name +
                "' says the time is in " + TimeUnitName(*columns.time_unit) +
                " but --odometry_time_unit is " + TimeUnitName(unit) +
                "; drop the flag or rename the column");
  }
  return *columns.time_unit;
}

// --wheel_ticks_per_m converts the counts of a wheel-tick log; with any
// other log it would go unused, and a user who gave it expects ticks.
void CheckTicksPerMetreUsed(const std::string& path,
                            const WheelTravelOptions& wheels,
                            const std::string& log) {
  if (wheels.ticks_per_m > 0.0) {
    throw FormatError(path + ": --wheel_ticks_per_m is given, but this is " +
                      log +
                      ", not wheel ticks (timestamp,left_ticks,right_ticks); "
                      "drop the flag");
  }
}

// The rows of a wheel-travel CSV after its header `fields`, integrated with
// the nominal track (wheel_travel.h). Ticks are converted from their count
// relative to the first row, in integers, so that large counters keep their
// precision; a difference beyond the int64 range is refused.
Trajectory ReadWheelRows(LineReader* reader,
                         const std::vector<std::string_view>& fields,
                         TimeUnit unit,
                         bool unit_given,
                         const WheelTravelOptions& wheels,
                         const std::string& format_hint) {
  std::string error;
  const std::optional<WheelCsvColumns> columns =
      ParseWheelCsvHeader(fields, &error);
  if (!columns) reader->Fail(error + format_hint);
  const std::string column_list =
      columns->time_name + "," + columns->left_name + "," + columns->right_name;
  if (!(wheels.track_m > 0.0)) {
    reader->Fail("wheel travels (" + column_list +
                 ") are integrated with the nominal wheel track: pass "
                 "--wheel_track_m");
  }
  if (columns->ticks && !(wheels.ticks_per_m > 0.0)) {
    reader->Fail("wheel ticks (" + column_list +
                 ") need the encoder ticks per metre: pass "
                 "--wheel_ticks_per_m");
  }
  const TimeUnit time_unit = [&] {
    OdometryCsvColumns time_column;
    time_column.time_name = columns->time_name;
    time_column.time_unit = columns->time_unit;
    return TimeColumnUnit(*reader, time_column, unit, unit_given);
  }();
  WheelTravels travels;
  travels.source = reader->path();
  IncreasingStamps increasing;
  int64_t first_left_ticks = 0, first_right_ticks = 0;
  const auto ticks_to_m =
      [&](int64_t ticks, int64_t first, const std::string& column) {
        int64_t count = 0;
        if (__builtin_sub_overflow(ticks, first, &count)) {
          reader->Fail("column '" + column + "': " + std::to_string(ticks) +
                       " is more than the 64-bit integer range away from the "
                       "first row's " +
                       std::to_string(first));
        }
        return static_cast<double>(count) / wheels.ticks_per_m;
      };
  std::string line;
  while (reader->Next(&line)) {
    const std::vector<std::string_view> row = SplitFields(line);
    CheckFieldCount(*reader, row, 3, column_list, false, "");
    WheelTravelSample sample;
    sample.stamp_ns =
        ParseStamp(*reader, row[columns->time], time_unit, columns->time_name);
    if (columns->ticks) {
      const int64_t left =
          ParseTicks(*reader, row[columns->left], columns->left_name);
      const int64_t right =
          ParseTicks(*reader, row[columns->right], columns->right_name);
      if (travels.samples.empty()) {
        first_left_ticks = left;
        first_right_ticks = right;
      }
      sample.left_m = ticks_to_m(left, first_left_ticks, columns->left_name);
      sample.right_m =
          ticks_to_m(right, first_right_ticks, columns->right_name);
    } else {
      sample.left_m =
          columns->left_to_m *
          ParseValue(*reader, row[columns->left], columns->left_name);
      sample.right_m =
          columns->right_to_m *
          ParseValue(*reader, row[columns->right], columns->right_name);
    }
    increasing.Check(*reader, sample.stamp_ns, row[columns->time]);
    travels.samples.push_back(sample);
  }
  if (travels.samples.empty()) reader->FailNoData();
  if (!columns->ticks) {
    CheckTicksPerMetreUsed(
        reader->path(), wheels, "a wheel-travel log (" + column_list + ")");
  }
  Trajectory trajectory = IntegrateWheelTravels(travels, wheels.track_m);
  trajectory.time_unit = time_unit;  // as read (a header suffix wins)
  return trajectory;
}

Trajectory ReadCsv(const std::string& path,
                   TimeUnit unit,
                   bool unit_given,
                   const WheelTravelOptions& wheels,
                   const std::string& format_hint) {
  Trajectory trajectory;
  trajectory.source = path;
  trajectory.planar = true;
  LineReader reader(path);
  IncreasingStamps increasing;
  OdometryCsvColumns columns;
  std::string column_list = kCsvColumnList;
  TimeUnit time_unit = unit;
  bool yaw_unit_named = false;
  double previous_yaw = 0.0;
  std::string line;
  bool first = true;
  while (reader.Next(&line)) {
    const std::vector<std::string_view> fields = SplitFields(line);
    const bool is_header = first && !fields.empty() && !LooksNumeric(fields[0]);
    const bool first_data_line = first;
    first = false;
    if (is_header) {
      if (LooksLikeWheelCsvHeader(fields)) {
        return ReadWheelRows(
            &reader, fields, unit, unit_given, wheels, format_hint);
      }
      if (fields.size() != 4) {
        reader.Fail("header has " + std::to_string(fields.size()) +
                    " fields, expected 4 (" + kCsvColumnList + ") or 3 (" +
                    kWheelColumnList + ")" + format_hint);
      }
      std::string error;
      const std::optional<OdometryCsvColumns> named =
          ParseOdometryCsvHeader(fields, &error);
      if (!named) reader.Fail(error + format_hint);
      columns = *named;
      time_unit = TimeColumnUnit(reader, columns, unit, unit_given);
      yaw_unit_named = std::string_view(columns.yaw_name).find('_') !=
                       std::string_view::npos;
      column_list.clear();
      for (size_t i = 0; i < fields.size(); ++i) {
        column_list += (i == 0 ? "" : ",") + std::string(fields[i]);
      }
      continue;
    }
    CheckFieldCount(
        reader, fields, 4, column_list, first_data_line, format_hint);
    StampedPose pose;
    pose.stamp_ns =
        ParseStamp(reader, fields[columns.time], time_unit, columns.time_name);
    const double x =
        columns.x_to_m * ParseValue(reader, fields[columns.x], columns.x_name);
    const double y =
        columns.y_to_m * ParseValue(reader, fields[columns.y], columns.y_name);
    const double yaw =
        columns.yaw_to_rad *
        ParseValue(reader, fields[columns.yaw], columns.yaw_name);
    increasing.Check(reader, pose.stamp_ns, fields[columns.time]);
    if (!trajectory.poses.empty()) {
      if (const std::optional<std::string> problem =
              YawStepProblem(previous_yaw, yaw, yaw_unit_named)) {
        reader.Fail(*problem);
      }
    }
    previous_yaw = yaw;
    pose.world_from_sensor.rotation = YawRotation(yaw);
    pose.world_from_sensor.translation = Eigen::Vector3d(x, y, 0.0);
    trajectory.poses.push_back(pose);
  }
  if (trajectory.poses.empty()) reader.FailNoData();
  CheckTicksPerMetreUsed(
      path, wheels, "a pose odometry log (" + column_list + ")");
  trajectory.time_unit = time_unit;
  return trajectory;
}

}  // namespace

Trajectory ReadTumTrajectory(const std::string& path, TimeUnit unit) {
  return ReadTum(path, unit, "");
}

Trajectory ReadOdometryCsv(const std::string& path,
                           TimeUnit unit,
                           bool unit_given,
                           const WheelTravelOptions& wheels) {
  return ReadCsv(path, unit, unit_given, wheels, "");
}

OdometryFormat ParseOdometryFormat(const std::string& name) {
  if (name == "auto") return OdometryFormat::kAuto;
  if (name == "tum") return OdometryFormat::kTum;
  if (name == "csv") return OdometryFormat::kCsv;
  throw std::invalid_argument(
      "odometry format: expected one of auto, tum, csv; got '" + name + "'");
}

const char* OdometryFormatName(OdometryFormat format) {
  switch (format) {
    case OdometryFormat::kTum:
      return "tum";
    case OdometryFormat::kCsv:
      return "csv";
    case OdometryFormat::kAuto:
      break;
  }
  return "auto";
}

Trajectory ReadOdometry(const std::string& path,
                        OdometryFormat format,
                        TimeUnit unit,
                        bool unit_given,
                        const WheelTravelOptions& wheels) {
  std::string reason;
  if (format == OdometryFormat::kAuto) {
    size_t num_fields = 0;
    int line_number = 0;
    const std::string extension = LowercaseExtension(path);
    if (const std::optional<OdometryFormat> by_content =
            FormatByContent(path, &num_fields, &line_number)) {
      format = *by_content;
      reason = "its first data line";
    } else if (extension == ".csv") {
      format = OdometryFormat::kCsv;
      reason = "its extension " + extension;
    } else if (extension == ".tum" || extension == ".txt") {
      format = OdometryFormat::kTum;
      reason = "its extension " + extension;
    } else {
      ThrowAt(path,
              line_number,
              "cannot tell the odometry format from " +
                  std::to_string(num_fields) + " fields; expected 4 (" +
                  kCsvColumnList + ") or 8 (TUM: " + kTumColumnList +
                  "); pass --odometry_format csv or tum");
    }
  } else {
    reason = std::string("--odometry_format ") + FormatName(format);
  }
  const std::string format_hint = std::string(" (read as ") +
                                  FormatName(format) + " because of " + reason +
                                  "; --odometry_format csv or tum chooses)";
  if (format == OdometryFormat::kCsv) {
    return ReadCsv(path, unit, unit_given, wheels, format_hint);
  }
  Trajectory trajectory = ReadTum(path, unit, format_hint);
  CheckTicksPerMetreUsed(
      path, wheels, std::string("a TUM pose log (") + kTumColumnList + ")");
  return trajectory;
}

void WriteTumTrajectory(const Trajectory& trajectory, const std::string& path) {
  std::ofstream stream = OpenForWriting(path);
  stream << "# " << kTumColumnList << "\n";
  for (const StampedPose& pose : trajectory.poses) {
    const Eigen::Vector3d& t = pose.world_from_sensor.translation;
    const Eigen::Quaterniond& q = pose.world_from_sensor.rotation;
    stream << FormatTimestampSeconds(pose.stamp_ns) << ' ' << FormatValue(t.x())
           << ' ' << FormatValue(t.y()) << ' ' << FormatValue(t.z()) << ' '
           << FormatValue(q.x()) << ' ' << FormatValue(q.y()) << ' '
           << FormatValue(q.z()) << ' ' << FormatValue(q.w()) << '\n';
  }
  FinishWriting(stream, path);
}

void WriteOdometryCsv(const Trajectory& trajectory, const std::string& path) {
  for (size_t i = 0; i < trajectory.poses.size(); ++i) {
    const Rigid3d& pose = trajectory.poses[i].world_from_sensor;
    const Eigen::Quaterniond q = pose.rotation.normalized();
    if (std::abs(pose.translation.z()) > kPlanarTolerance ||
        std::abs(q.x()) > kPlanarTolerance ||
        std::abs(q.y()) > kPlanarTolerance) {
      throw std::invalid_argument(
          "trajectory.poses[" + std::to_string(i) +
          "]: not planar (z or roll/pitch non-zero); cannot write it as "
          "timestamp,x,y,yaw");
    }
  }
  std::ofstream stream = OpenForWriting(path);
  stream << kCsvColumnList << "\n";
  for (const StampedPose& pose : trajectory.poses) {
    const Eigen::Vector3d& t = pose.world_from_sensor.translation;
    const Eigen::Quaterniond q =
        WithPositiveScalar(pose.world_from_sensor.rotation.normalized());
    const double yaw = 2.0 * std::atan2(q.z(), q.w());
    stream << FormatTimestampSeconds(pose.stamp_ns) << ',' << FormatValue(t.x())
           << ',' << FormatValue(t.y()) << ',' << FormatValue(yaw) << '\n';
  }
  FinishWriting(stream, path);
}

void WriteWheelTravelCsv(const WheelTravels& travels, const std::string& path) {
  std::ofstream stream = OpenForWriting(path);
  stream << kWheelColumnList << "\n";
  for (const WheelTravelSample& sample : travels.samples) {
    stream << FormatTimestampSeconds(sample.stamp_ns) << ','
           << FormatValue(sample.left_m) << ',' << FormatValue(sample.right_m)
           << '\n';
  }
  FinishWriting(stream, path);
}

}  // namespace odomcal
