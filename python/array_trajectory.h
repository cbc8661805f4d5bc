// Trajectories from numeric arrays (the Python module's numpy arrays), with
// the checks of the file readers (trajectory_io.h) and messages that name
// the array and row instead of a file and line:
//   "camera_poses row 3: quaternion (qx qy qz qw) has norm 0.5, more than
//    0.01 away from 1"
// Column 0 is the time in `unit`, rounded to integer nanoseconds (a float64
// Unix time in seconds resolves about 0.2 us), unless the rows carry
// stamps_ns.
#pragma once

#include "odomcal/adapters/timestamp.h"
#include "odomcal/adapters/trajectory.h"

#include <cstdint>
#include <string>
#include <vector>

namespace odomcal {

// A 2-D array of numbers, row-major. With stamps_ns (one per row: integer
// nanoseconds given beside the values, e.g. numpy int64), column 0 is a
// placeholder and the times are these, exact, whatever the time unit.
struct NumericRows {
  size_t num_rows = 0;
  size_t num_cols = 0;
  std::vector<double> values;
  std::vector<int64_t> stamps_ns;
};

// N x 8 [t, tx, ty, tz, qx, qy, qz, qw], world_from_cam (TUM order: scalar
// last). `name` ("camera_poses") starts every message; the trajectory's
// source is "<name> (numpy array, N x 8)". Throws FormatError.
Trajectory CameraTrajectoryFromRows(const NumericRows& rows,
                                    TimeUnit unit,
                                    const std::string& name);

// M x 4 [t, x, y, yaw] (metres, radians; planar like an odometry CSV) or
// M x 8 TUM origin_from_odom. Throws FormatError.
Trajectory OdometryFromRows(const NumericRows& rows,
                            TimeUnit unit,
                            const std::string& name);

}  // namespace odomcal
