// The floor under a calibrated COLMAP project: the metric sub-models' points
// and cameras handed to the floor-plane fit (solver/floor_plane.h), and the
// calibration's translation z set from it where the floor is seen well
// enough (solver/floor_translation_z.h), with the metric models moved to
// that z.
#pragma once

#include "odomcal/plugin/colmap/colmap_calibration.h"
#include "odomcal/solver/floor_plane.h"

#include <map>
#include <string>
#include <vector>

namespace odomcal {

// The points of `models` with their position's standard deviation from
// their tracks: the angle of the larger of their reprojection error and
// 0.5 px over the focal length, times the distance to the nearest observing
// camera, divided by the sine of the largest angle between their rays
// (depth from triangulation), at least the lateral part.
std::vector<FloorCandidatePoint> FloorCandidatesOf(
    const std::vector<MetricSubModel>& models);

// The registered cameras of `models` in time order (`stamp_of_image`: image
// name to time; names missing from it sort by name after the others).
std::vector<FloorCamera> FloorCamerasOf(
    const std::vector<MetricSubModel>& models,
    const std::map<std::string, int64_t>& stamp_of_image);

// Fits the floor of run->metric_models (options.use != kOff), stores it in
// run->check.result.floor_plane and, when z is set from it (its standard
// deviation within max_translation_stddev_m), moves every metric model by
// the change of z. A floor that is sloped or disagrees with the motion adds
// a warning.
void ApplyFloorPlane(const FloorPlaneOptions& options,
                     double max_translation_stddev_m,
                     const std::map<std::string, int64_t>& stamp_of_image,
                     ColmapCalibrationRun* run);

}  // namespace odomcal
