// The floor under a calibrated COLMAP project: the metric sub-models' points
// and cameras handed to the floor-plane fit (solver/floor_plane.h), and the
// calibration's translation z set from it where the floor is seen well
// enough (solver/floor_translation_z.h), with the metric models moved to
// that z.
#pragma once

#include "odomcal/plugin/colmap/colmap_calibration.h"
#include "odomcal/solver/floor_plane.h"

#include <map>
#include <optional>
#include <string>
#include <vector>

namespace odomcal {

// fx / fy of a camera of two focal lengths (PINHOLE, OPENCV, ...); none for
// one focal length or params that do not give a positive finite ratio.
std::optional<double> PixelAspectOf(const ColmapCamera& camera);

// What the floor-plane fit takes from `models`: their registered cameras
// in time order (`stamp_of_image`: image name to time; names missing from
// it sort by name after the others), and their points with their position's
// standard deviation from their tracks: the angle of the larger of their
// reprojection error and 0.5 px over the focal length, times the distance to
// the nearest observing camera, divided by the sine of the largest angle
// between their rays (depth from triangulation), at least the lateral part;
// with that camera (its index in `cameras`) and that distance.
struct FloorInput {
  std::vector<FloorCandidatePoint> points;
  std::vector<FloorCamera> cameras;
};
FloorInput FloorInputOf(const std::vector<MetricSubModel>& models,
                        const std::map<std::string, int64_t>& stamp_of_image);

// Fits the floor of run->metric_models (options.use != kOff), stores it in
// run->check.result.floor_plane and, when z is set from it (its standard
// deviation within max_translation_stddev_m), moves every metric model by
// the change of z. A floor that is sloped, disagrees with the motion or
// whose tilt is too uncertain to tell adds a warning.
// `agreeing_joint_model`: the joint adjustment's model where its check
// agreed (joint_adjustment_stage.h), or null. The floor is fitted on it too,
// with the adjustment's extrinsic; where both fits see the floor, the
// difference of their camera heights goes into the height's standard
// deviation (FloorPlane::camera_height_model_difference_m).
void ApplyFloorPlane(const FloorPlaneOptions& options,
                     double max_translation_stddev_m,
                     const std::map<std::string, int64_t>& stamp_of_image,
                     const MetricSubModel* agreeing_joint_model,
                     ColmapCalibrationRun* run);

}  // namespace odomcal
