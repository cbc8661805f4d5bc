// The rig's section of a rig's report.html (`odomcal colmap` on a project
// with several cameras, colmap_rig_outputs.h): a table of the cameras, the
// transforms between calibrated cameras, the metric scales two cameras found
// for one sub-model, and a drawing of the calibrated cameras on the robot
// seen from above and from the side. Takes plain data; the CLI fills it.
#pragma once

#include "odomcal/plugin/colmap/colmap_rig_calibration.h"
#include "odomcal/solver/calibration_result.h"
#include "odomcal/solver/camera_pair.h"

#include <optional>
#include <string>
#include <vector>

namespace odomcal {

struct RigReportCamera {
  std::string name;
  std::string status;  // a calibration status name, or "input_error"
  std::string reason;  // the result's message or the input error
  // Rotation, x and y estimated with a covariance (ExtrinsicOf): the camera
  // is in the tables' numbers and in the drawing.
  bool calibrated = false;
  // odom_from_cam, its standard deviations, the metric scales, pairs used.
  CalibrationResult result;
  // odometry_time = camera_time + offset, seconds; absent when the run
  // had no clock offset step. Its sigma is 0 when it was held.
  std::optional<double> clock_offset_s;
  bool clock_offset_estimated = false;
  double clock_offset_stddev_s = 0.0;
  int num_images = 0;  // the camera's registered images
  // The camera's own report relative to the rig's ("cameras/front/
  // report.html"); empty when it has none.
  std::string report_path;
};

struct RigReportPair {
  int camera_a = 0;  // indices into RigReport::cameras
  int camera_b = 0;
  CameraPairTransform transform;  // camB_from_camA
  // From the rig's joint adjustment: the covariance holds the cross terms.
  bool adjusted_together = false;
};

struct RigReport {
  std::vector<RigReportCamera> cameras;
  int reference = 0;
  std::vector<RigReportPair> pairs;  // every two calibrated cameras
  // The cameras the rig's joint adjustment adjusted together (names); empty
  // when it did not run or failed.
  std::vector<std::string> adjusted_together;
  // Points of one COLMAP model that the adjustment's images of two or more
  // cameras see (one point each).
  int num_points_across_cameras = 0;
  // How the adjustment came to be reported ("--joint_adjustment on", or
  // the default check's contradiction) or, where it ran as a check that left
  // the cameras' own estimates, what it found; empty when it did not run.
  std::string joint_note;
  // Indices into `cameras`.
  std::vector<SharedSubModelScale> shared_scales;
};

// The section: "<h2>Cameras of the rig</h2>" and its tables and figure,
// self-contained HTML with inline SVG (no style sheet of its own: the
// report's table style applies). Throws std::invalid_argument for a camera
// index out of range.
std::string RigReportHtml(const RigReport& rig);

// The corners of the pyramid drawn for a camera in the section's figure,
// in the odometry frame: [0] the optical centre, [1..4] the base's corners
// `depth_m` along the optical axis (camera z), in the order image top-left,
// top-right, bottom-right, bottom-left (camera x right, y down).
std::vector<Eigen::Vector3d> CameraPyramid(const Rigid3d& odom_from_cam,
                                           double depth_m);

}  // namespace odomcal
