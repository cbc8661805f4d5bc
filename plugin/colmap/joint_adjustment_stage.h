// The joint adjustment stage of a project calibration: the two-step metric
// models (colmap_calibration.h) and the wheel odometry handed to
// AdjustJointly (solver/joint_adjustment.h), its extrinsic taken into the
// result and its model written as the metric model.
//
// The problem it builds:
//   - images: every image of the metric models, once by name, started at
//     its pose there (origin_from_cam composed with the two-step
//     cam_from_odom, its planar part);
//   - points: each sub-model's points once (a part of a sub-model cut by
//     the checks shares its points with the other parts), in metres;
//   - cameras: each sub-model's, with COLMAP's intrinsics (held unless
//     refined);
//   - odometry links: the calibration's motion pairs the odometry does not
//     contradict, their covariance the calibration's noise model (the
//     estimated one when estimated); and between consecutive pieces of the
//     drive (sub-models, or parts the checks cut), one link from the
//     odometry between the last image of one and the first of the next, so
//     that the pieces become one model.
#pragma once

#include "odomcal/plugin/colmap/colmap_calibration.h"

#include <cstdint>
#include <map>
#include <optional>
#include <string>

namespace odomcal {

// Runs the adjustment when inputs.joint_adjustment.use is kOn or kCheck and
// the two-step calibration gave an extrinsic and metric models; fills
// run->joint. Where it is taken (kOn, or kCheck beyond
// kJointContradictionSigmas of the two-step estimate), run->check.result
// holds the adjustment's extrinsic (the two-step one stays in run->joint)
// and run->metric_models the one adjusted model ("0"); a check within them
// leaves both as they were. Where it cannot run (a camera model it does not
// know, SE(3) odometry with z estimated) or does not succeed, the two-step
// result stays, with a warning under kOn.
// `stamp_of_image`: image name to time (camera clock). `progress`, when
// set, hears where the adjustment is ("joint adjustment: pass 2, iteration
// 14, 12 s").
// `agreeing_model`, when given: under kCheck with an adjustment that agreed
// (the two-step estimate stands), its model (metres; the odometry's frame
// up to a planar motion), for a second fit of the floor (floor_height.h);
// empty otherwise.
void ApplyJointAdjustment(
    const ColmapCalibrationInputs& inputs,
    const std::map<std::string, int64_t>& stamp_of_image,
    const CalibrationProgress& progress,
    ColmapCalibrationRun* run,
    std::optional<MetricSubModel>* agreeing_model = nullptr);

// The settings' adjustment options on every core, with `progress` (when
// set) hearing "<label>: pass 2, iteration 14, 12 s" (or "jackknife
// re-solve 3 of 8, ...") after each iteration, seconds counted from this
// call (the solver's own count restarts with the jackknife).
JointAdjustmentOptions JointOptionsWithProgress(
    const JointAdjustmentSettings& settings,
    const CalibrationProgress& progress,
    const std::string& label);

}  // namespace odomcal
