#include "odomcal/python/array_trajectory.h"

#include "odomcal/adapters/format_error.h"
#include "odomcal/adapters/input_plausibility.h"
#include "odomcal/solver/format_number.h"
#include "odomcal/solver/rigid3.h"

#include <cmath>
#include <optional>
#include <string>

namespace odomcal {
namespace {

constexpr double kMaxQuaternionNormDeviation = 1e-2;  // as the TUM reader

int64_t NanosecondsPer(TimeUnit unit) {
  switch (unit) {
    case TimeUnit::kSeconds:
      return 1000000000;
    case TimeUnit::kMilliseconds:
      return 1000000;
    case TimeUnit::kMicroseconds:
      return 1000;
    case TimeUnit::kNanoseconds:
      return 1;
  }
  return 1;
}

class RowChecker {
 public:
  RowChecker(const NumericRows& rows, TimeUnit unit, const std::string& name)
      : rows_(rows), unit_(unit), name_(name) {}

  [[noreturn]] void Fail(size_t row, const std::string& what) const {
    throw FormatError(name_ + " row " + std::to_string(row) + ": " + what);
  }

  void CheckShape(const std::vector<size_t>& allowed_cols,
                  const std::string& columns) const {
    bool allowed = false;
    for (const size_t cols : allowed_cols) allowed |= rows_.num_cols == cols;
    if (!allowed && Paired()) {
      // The values beside the times: the shapes without the time column.
      std::string without_time = columns;
      for (const size_t cols : allowed_cols) {
        const std::string with = "(N, " + std::to_string(cols) + ") [t, ";
        for (size_t at = without_time.find(with); at != std::string::npos;
             at = without_time.find(with)) {
          without_time.replace(
              at, with.size(), "(N, " + std::to_string(cols - 1) + ") [");
        }
      }
      throw FormatError(name_ + ": expected values of shape " + without_time +
                        " beside the times, got (" +
                        std::to_string(rows_.num_rows) + ", " +
                        std::to_string(rows_.num_cols - 1) + ")");
    }
    if (!allowed) {
      throw FormatError(name_ + ": expected an array of shape " + columns +
                        ", got (" + std::to_string(rows_.num_rows) + ", " +
                        std::to_string(rows_.num_cols) + ")");
    }
    if (rows_.num_rows == 0)
      throw FormatError(name_ + ": the array has no rows");
  }

  // Finite, with the column's name in the message.
  double Value(size_t row, size_t col, const char* column) const {
    const double value = rows_.values[row * rows_.num_cols + col];
    if (!std::isfinite(value)) {
      Fail(row,
           std::string("column '") + column + "' is not finite (NaN or Inf)");
    }
    return value;
  }

  // Column 0 in nanoseconds, strictly after the previous row's.
  int64_t StampNs(size_t row) {
    const int64_t stamp_ns = Paired() ? rows_.stamps_ns.at(row) : Rounded(row);
    if (row > 0 && stamp_ns <= previous_ns_) {
      Fail(row,
           std::string(stamp_ns == previous_ns_ ? "duplicate time"
                                                : "time not increasing") +
               " (" + FormatTimestampSeconds(stamp_ns) + " s after " +
               FormatTimestampSeconds(previous_ns_) + " s in row " +
               std::to_string(row - 1) + ")");
    }
    previous_ns_ = stamp_ns;
    return stamp_ns;
  }

  // Columns 1..7: tx ty tz qx qy qz qw.
  Rigid3d TumPose(size_t row) const {
    const Eigen::Vector3d translation(
        Value(row, 1, "tx"), Value(row, 2, "ty"), Value(row, 3, "tz"));
    // Array order qx qy qz qw; Eigen's constructor takes w, x, y, z.
    const Eigen::Quaterniond rotation(Value(row, 7, "qw"),
                                      Value(row, 4, "qx"),
                                      Value(row, 5, "qy"),
                                      Value(row, 6, "qz"));
    const double norm = rotation.norm();
    if (std::abs(norm - 1.0) > kMaxQuaternionNormDeviation) {
      Fail(row,
           "quaternion (qx qy qz qw) has norm " + FormatNumber(norm) +
               ", more than " + FormatNumber(kMaxQuaternionNormDeviation) +
               " away from 1");
    }
    return Rigid3d(rotation.normalized(), translation);
  }

  std::string Source() const {
    if (Paired()) {
      return name_ + " (numpy arrays, " + std::to_string(rows_.num_rows) +
             " int64 ns times and " + std::to_string(rows_.num_rows) + " x " +
             std::to_string(rows_.num_cols - 1) + " values)";
    }
    return name_ + " (numpy array, " + std::to_string(rows_.num_rows) + " x " +
           std::to_string(rows_.num_cols) + ")";
  }

 private:
  bool Paired() const { return !rows_.stamps_ns.empty(); }

  // Column 0 in `unit_`, rounded to nanoseconds.
  int64_t Rounded(size_t row) const {
    const int64_t per_unit = NanosecondsPer(unit_);
    const double time = Value(row, 0, "timestamp");
    const double ns = time * static_cast<double>(per_unit);
    // 2^63 is exactly representable; anything at or above it overflows.
    if (!(std::abs(ns) < 9223372036854775808.0)) {
      Fail(row,
           "time " + FormatNumber(time) + " " + TimeUnitName(unit_) +
               " is beyond the int64 nanosecond range (about 292 years); "
               "check the time unit");
    }
    return std::llround(ns);
  }

  const NumericRows& rows_;
  TimeUnit unit_;
  std::string name_;
  int64_t previous_ns_ = 0;
};

Trajectory TumFromRows(RowChecker& checker, size_t num_rows) {
  Trajectory trajectory;
  for (size_t row = 0; row < num_rows; ++row) {
    StampedPose pose;
    pose.stamp_ns = checker.StampNs(row);
    pose.world_from_sensor = checker.TumPose(row);
    trajectory.poses.push_back(pose);
  }
  trajectory.source = checker.Source();
  return trajectory;
}

}  // namespace

Trajectory CameraTrajectoryFromRows(const NumericRows& rows,
                                    TimeUnit unit,
                                    const std::string& name) {
  RowChecker checker(rows, unit, name);
  checker.CheckShape({8}, "(N, 8) [t, tx, ty, tz, qx, qy, qz, qw]");
  return TumFromRows(checker, rows.num_rows);
}

Trajectory OdometryFromRows(const NumericRows& rows,
                            TimeUnit unit,
                            const std::string& name) {
  RowChecker checker(rows, unit, name);
  checker.CheckShape(
      {4, 8},
      "(N, 4) [t, x, y, yaw] or (N, 8) [t, tx, ty, tz, qx, qy, qz, qw]");
  if (rows.num_cols == 8) return TumFromRows(checker, rows.num_rows);
  Trajectory trajectory;
  trajectory.planar = true;
  double previous_yaw = 0.0;
  for (size_t row = 0; row < rows.num_rows; ++row) {
    StampedPose pose;
    pose.stamp_ns = checker.StampNs(row);
    const double x = checker.Value(row, 1, "x");
    const double y = checker.Value(row, 2, "y");
    const double yaw = checker.Value(row, 3, "yaw");
    if (row > 0) {
      if (const std::optional<std::string> problem =
              YawStepProblem(previous_yaw, yaw, /*yaw_unit_named=*/true)) {
        checker.Fail(row, *problem + " (yaw must be in radians)");
      }
    }
    previous_yaw = yaw;
    pose.world_from_sensor =
        Rigid3d(YawRotation(yaw), Eigen::Vector3d(x, y, 0.0));
    trajectory.poses.push_back(pose);
  }
  trajectory.source = checker.Source();
  return trajectory;
}

}  // namespace odomcal
