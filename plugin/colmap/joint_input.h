// The joint adjustment's problem (solver/joint_adjustment.h) from a project
// calibration (colmap_calibration.h): its metric models' images, points and
// cameras, and the odometry between the images' times as links. Shared by
// one camera's adjustment (joint_adjustment_stage.h) and a rig's
// (rig_joint_adjustment.h).
#pragma once

#include "odomcal/plugin/colmap/colmap_calibration.h"
#include "odomcal/solver/joint_adjustment.h"

#include <cstdint>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace odomcal {

// The problem and where each of its parts came from.
struct JointInput {
  JointAdjustmentProblem problem;
  std::vector<std::string> image_names;  // per joint image
  std::vector<int64_t> image_stamps_ns;  // odometry clock
  std::vector<const ColmapImage*> source_images;
  std::vector<const ColmapCamera*> source_cameras;
  std::vector<const ColmapPoint3D*> source_points;
  // Per point, the reconstruction's point it is (whichever camera's
  // calibration it came through), or none where that is not known.
  std::vector<std::optional<ReconstructionPoint>> reconstruction_points;
  std::vector<uint32_t> observation_point2D;  // index into the image's list
  // Per link, the motion pair it was made from (stamps on the odometry's
  // clock), for attaching the logged odometry.
  MotionPairs link_pairs;
  int num_joining_links = 0;
  // The odometry as logged, read once by AddOdometrySystematics and kept
  // for the problems built again from this input.
  std::shared_ptr<const Trajectory> logged_odometry;
};

// The odometry's motion between two image times (odometry clock) as a link
// between images i and j, planar and whole (OdometryLink::motion_3d), its
// covariance the calibration's noise model (the estimated one when `fit`
// estimated it).
OdometryLink LinkOf(const MotionPair& pair,
                    int image_i,
                    int image_j,
                    const CalibrationResult& fit,
                    const NoiseModel& given);

// The odometry's motion from stamp a to stamp b (odometry clock) with its
// interpolation covariance; none where either lies outside the odometry or
// in a gap of it.
std::optional<MotionPair> OdometryMotionBetween(const ColmapCalibrationRun& run,
                                                int64_t stamp_a_ns,
                                                int64_t stamp_b_ns);

// The images (started at their pose in the metric models composed with the
// calibration's cam_from_odom), points (metres) and cameras of
// run.metric_models, appended to input; "" or why the adjustment cannot
// take them (a camera model it does not project, no timed image).
// `stamp_of_image`: image name to time (camera clock). `intrinsics`: with
// kAuto a camera is held (JointCamera::held) unless COLMAP's bundle
// adjustment changed its intrinsics from run.database_cameras'.
std::string AddMetricModels(
    const ColmapCalibrationRun& run,
    const std::map<std::string, int64_t>& stamp_of_image,
    JointIntrinsics intrinsics,
    JointInput* input);

// The calibration's motion pairs the odometry does not contradict, as
// links; then one link from the odometry between consecutive pieces of the
// drive (sub-models, or parts the checks cut), so that they become one
// model. Sets the problem's motion model (MotionModelOf).
void AddOdometryLinks(const ColmapCalibrationInputs& inputs,
                      const ColmapCalibrationRun& run,
                      JointInput* input);

// Whole robot poses either way: kSE3 where the links' odometry leaves the
// plane (a 3-D log, whose tilts and height follow the ground), kOnGround
// where every link is planar (IsPlanarMotion: a planar log, or a 3-D one of
// a level floor), whose robot may still pitch and bank with the ground.
RobotMotionModel MotionModelOf(const MotionPairs& links);

// The odometry's systematics refined in the adjustment where the two-step
// estimated them (its intrinsics, and its clock offset when
// `refine_time_offset`), from the logged odometry (before its intrinsics
// correction) between each link's images: a planar log only. Call after
// the links are added (input->link_pairs). Reads the log into
// input->logged_odometry unless it holds it.
void AddOdometrySystematics(const ColmapCalibrationInputs& inputs,
                            const ColmapCalibrationRun& run,
                            bool refine_time_offset,
                            JointInput* input);

}  // namespace odomcal
