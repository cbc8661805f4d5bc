// Shared by the writers of rendered datasets (rendered_dataset.cc,
// rendered_rig.cc): the JSON pieces of ground_truth.json, text and PNG
// files; internal: not installed.
#pragma once

#include "odomcal/datasets/rendering/camera_model.h"
#include "odomcal/datasets/rendering/ray_caster.h"
#include "odomcal/datasets/rendering/rendered_dataset.h"
#include "odomcal/solver/rigid3.h"

#include <nlohmann/json.hpp>

#include <string>

namespace odomcal::internal {

// quaternion_wxyz (positive w), translation_m and the 4x4 matrix.
nlohmann::json TransformJson(const Rigid3d& transform);

// COLMAP model, width, height, params and param_names.
nlohmann::json IntrinsicsJson(const CameraIntrinsics& camera);

// name, timestamp, capture_timestamp and world_from_cam (no matrix).
nlohmann::json FrameJson(const RenderedFrame& frame);

// Throws std::runtime_error naming the path when writing fails.
void WriteTextFile(const std::string& path, const std::string& text);

// 8-bit RGB PNG; throws std::runtime_error naming the path.
void WritePng(const Image& image, const std::string& path);

// odometry.csv, odometry_ground_truth.csv and, for roads, odometry_se3.tum
// of the drive into `output_dir` (see WriteRenderedDataset).
void WriteOdometryFiles(const RenderedDataset& dataset,
                        const std::string& output_dir);

}  // namespace odomcal::internal
