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
// and rotation YawRotation(yaw); the Trajectory is marked planar.
// An optional header line names the columns: the first non-comment line is
// taken as a header when its first field does not start like a number. Its
// grammar (odometry_csv_header.h): four names in any order, any case,
//   t|time|timestamp[_s|_ms|_us|_ns], x[_m|_cm|_mm], y[_m|_cm|_mm],
//   yaw|theta[_rad|_deg]
// e.g. "time,x_mm,y_mm,yaw_deg" or "timestamp,yaw,x,y". Values are converted
// to metres and radians; the time is parsed exactly in the suffix's unit.
// Without a suffix, and in a file without a header (timestamp,x,y,yaw), the
// units are the time unit passed in, metres and radians. Errors: an unknown,
// duplicate or missing name (the message lists the accepted ones); a time
// suffix that contradicts a time unit the user gave (unit_given); a yaw step
// of more than pi between consecutive samples that is not a 2 pi wrap
// (degrees read as radians; input_plausibility.h).
//
// Wheel-travel CSV (wheel_travel.h), recognised by its header, which it
// needs (odometry_csv_header.h: a name whose base is left or right):
//   timestamp,left_m,right_m        cumulative travel of each wheel
//   timestamp,left_ticks,right_ticks cumulative encoder counts (int64)
// (any order, any case; time suffixes as above; distances also in _cm or
// _mm). The travels are integrated with the nominal track
// WheelTravelOptions::track_m into the planar trajectory, counts with
// ticks_per_m; without either one needed the header line's error names the
// flag: "path:1: wheel travels (timestamp,left_m,right_m) are integrated
// with the nominal wheel track: pass --wheel_track_m", "path:1: wheel ticks
// (timestamp,left_ticks,right_ticks) need the encoder ticks per metre: pass
// --wheel_ticks_per_m". Counts are not assumed to wrap around; a decreasing
// count is driving backwards. Rows are checked as for the pose CSV (a tick
// that is not an integer: "column 'left_ticks' is not an integer tick
// count: '12.5'").
// ticks_per_m given with any log but a wheel-tick one (a pose CSV, a TUM
// log through ReadOdometry, travels in distance) would go unused: "path:
// --wheel_ticks_per_m is given, but this is a pose odometry log
// (timestamp,x,y,yaw), not wheel ticks (timestamp,left_ticks,right_ticks);
// drop the flag".
//
// Both readers: timestamps are parsed exactly in `unit` (see timestamp.h);
// lines whose first non-blank character is '#' and blank lines are skipped;
// trailing '\r' and a UTF-8 byte order mark before the first line are
// ignored. Every problem throws FormatError whose message is
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
#include "odomcal/adapters/wheel_travel.h"

#include <string>

namespace odomcal {

// Reads a TUM trajectory (see above). planar = false.
Trajectory ReadTumTrajectory(const std::string& path, TimeUnit unit);

// Reads an odometry CSV (see above). planar = true. `unit` applies to a time
// column without a unit suffix; when `unit_given` (the user chose it with
// --odometry_time_unit), a header suffix naming another unit is an error.
// `wheels` integrates a wheel-travel CSV (see above).
Trajectory ReadOdometryCsv(const std::string& path,
                           TimeUnit unit,
                           bool unit_given = false,
                           const WheelTravelOptions& wheels = {});

enum class OdometryFormat { kAuto, kTum, kCsv };

// "auto", "tum" or "csv"; throws std::invalid_argument otherwise.
OdometryFormat ParseOdometryFormat(const std::string& name);
// The name ParseOdometryFormat reads.
const char* OdometryFormatName(OdometryFormat format);

// Reads an odometry log as TUM or CSV. kAuto decides by the content: the
// first data line (header and comments skipped) with 4 fields -> CSV, 8
// fields -> TUM, whatever the extension (a CSV named .txt is read as CSV);
// for any other count by the extension (".csv" -> CSV; ".tum", ".txt" ->
// TUM; case-insensitive), and without one a FormatError asks for
// --odometry_format. A wrong field count on the first data line or a bad
// header says how the format was chosen and names --odometry_format, e.g.
//   "path:1: expected 8 fields (...), got 4 (read as tum because of
//    --odometry_format tum; --odometry_format csv or tum chooses)".
// A wheel-travel header makes it CSV. `unit`, `unit_given` and `wheels` as
// for ReadOdometryCsv.
Trajectory ReadOdometry(const std::string& path,
                        OdometryFormat format,
                        TimeUnit unit,
                        bool unit_given = false,
                        const WheelTravelOptions& wheels = {});

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

// Writes a "timestamp,left_m,right_m" wheel-travel CSV (header line, exact
// decimal seconds, %.17g metres) that ReadOdometry reads back to the same
// travels. I/O errors throw FormatError.
void WriteWheelTravelCsv(const WheelTravels& travels, const std::string& path);

}  // namespace odomcal
