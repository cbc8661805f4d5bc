// `odomcal run --rig`: an image folder in COLMAP's rig layout, each
// sub-folder of --image_path one camera named by it (images/front/...,
// images/rear/...), against one odometry. Each camera is reconstructed and
// calibrated by the single-camera pipeline in WS/cameras/<name>/ (its own
// COLMAP database and model, its own scale and clock offset); the rig's
// files (rig outputs of colmap_rig_outputs.h) are written in WS.
//
// The cameras are not matched with each other: each camera's model has a
// scale of its own, and the camera-to-camera transforms come from the
// cameras' extrinsics (solver/camera_pair.h).
#pragma once

#include "odomcal/plugin/colmap/reconstruction_pipeline.h"

#include <nlohmann/json.hpp>

#include <map>
#include <string>
#include <vector>

namespace odomcal {

// The cameras of a rig folder: its sub-folders, in name order. Throws
// std::invalid_argument naming --rig when an image lies directly in
// `image_path` (in no camera's folder), when a sub-folder holds no image,
// and naming the camera folder when its name cannot be a frame name.
std::vector<std::string> RigCameraFolders(const std::string& image_path);

// --camera_params values (one per occurrence): NAME=PARAMS per camera, or
// one PARAMS for every camera. Returns name -> params for every camera
// given (a camera without is estimated by COLMAP). Throws
// std::invalid_argument naming --camera_params for a NAME that is no
// camera (listing `cameras`, "the cameras of <cameras_from>"), a camera
// given twice, or PARAMS for every camera mixed with NAME=PARAMS.
std::map<std::string, std::string> RigCameraParams(
    const std::vector<std::string>& values,
    const std::vector<std::string>& cameras,
    const std::string& cameras_from = "--image_path");

// Runs every camera, writes the rig's outputs, prints progress and the
// summary; returns the exit code (0 when any camera is calibrated). `run`
// holds the flags (its camera_params unused: `camera_params`);
// `camera_models` the COLMAP model of cameras whose model is not
// run.camera_model (name -> model, e.g. from a bag's CameraInfo).
int RunRigReconstruction(
    const ReconstructionOptions& run,
    const std::vector<std::string>& camera_params,
    const std::string& reference_camera,
    const nlohmann::json& bag_echo,
    const std::map<std::string, std::string>& camera_models = {});

}  // namespace odomcal
