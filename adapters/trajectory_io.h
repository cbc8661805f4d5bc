// Reading and writing pose logs: TUM trajectories and planar odometry CSV.
//
// TUM RGB-D trajectory format (one pose per line):
//   timestamp tx ty tz qx qy qz qw
// world_from_sensor: (tx, ty, tz) is the sensor origin in the world frame and
// the quaternion, in the order qx qy qz qw (scalar LAST, Hamilton), rotates
// sensor coordinates into the world frame. Fields are separated by whitespace
// or by commas.
//
// Odometry CSV (one sample per line):
//   timestamp,x,y,yaw
// origin_from_odom of a planar vehicle: x, y in metres, yaw in radians about
// +z (counter-clockwise seen from above). The pose is translation (x, y, 0)
// and rotation YawRotation(yaw); the Trajectory is marked planar. An optional
// header line is allowed: the first non-comment line is taken as a header
// when its first field does not start like a number; it must have 4 fields.
//
// Both readers: timestamps are parsed exactly in `unit` (see timestamp.h);
// lines whose first non-blank character is '#' and blank lines are skipped;
// trailing '\r' is ignored. Every problem throws FormatError whose message is
// "path:line: what is wrong" (or "path: what is wrong" when no line applies):
//   - the file cannot be opened ("cannot open for reading");
//   - no data lines ("no data lines");
//   - wrong number of fields ("expected 8 fields (...), got 7");
//   - a field that is empty, not a number, or out of range (names the column);
//   - a NaN or infinite value (names the column);
//   - a timestamp rejected by ParseTimestampNs (its reason, e.g. the
//     plausibility guard for a nanosecond log read as seconds);
//   - a quaternion whose norm differs from 1 by more than 1e-2 (smaller
//     deviations are normalized away);
//   - a timestamp equal to ("duplicate") or before ("not increasing") the
//     previous one; logs are never sorted silently.
// Trajectory::source is set to `path`.
#pragma once

#include "odomcal/adapters/format_error.h"
#include "odomcal/adapters/timestamp.h"
#include "odomcal/adapters/trajectory.h"

#include <string>

namespace odomcal {

// Reads a TUM trajectory (see above). planar = false.
Trajectory ReadTumTrajectory(const std::string& path, TimeUnit unit);

// Reads a timestamp,x,y,yaw odometry log (see above). planar = true.
Trajectory ReadOdometryCsv(const std::string& path, TimeUnit unit);

enum class OdometryFormat { kAuto, kTum, kCsv };

// "auto", "tum" or "csv"; throws std::invalid_argument otherwise.
OdometryFormat ParseOdometryFormat(const std::string& name);

// Reads an odometry log as TUM or CSV. kAuto decides by extension first
// (".csv" -> CSV; ".tum", ".txt" -> TUM; case-insensitive), then by the first
// data line (header and comments skipped): 4 fields -> CSV, 8 fields -> TUM,
// anything else -> FormatError asking for an explicit format.
Trajectory ReadOdometry(const std::string& path,
                        OdometryFormat format,
                        TimeUnit unit);

// Writes a TUM trajectory: a '#' header comment, then one line per pose with
// the timestamp in exact decimal seconds (FormatTimestampSeconds) and the
// values with 17 significant digits, quaternion in the order qx qy qz qw.
// Reading it back with TimeUnit::kSeconds reproduces the stamps exactly and
// the poses to rounding. Throws FormatError ("path: cannot open for writing",
// "path: write failed") on I/O errors.
void WriteTumTrajectory(const Trajectory& trajectory, const std::string& path);

// Writes a "timestamp,x,y,yaw" CSV with a header line; timestamps in exact
// decimal seconds, yaw in [-pi, pi]. Every pose must be planar (|z| and the
// x, y quaternion components at most 1e-9), otherwise std::invalid_argument
// is thrown before the file is touched. I/O errors throw FormatError.
void WriteOdometryCsv(const Trajectory& trajectory, const std::string& path);

}  // namespace odomcal
