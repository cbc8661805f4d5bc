// Calibration of an existing COLMAP project against wheel odometry: the
// shared core of `odomcal colmap` and `odomcal run`.
//
// Steps: read every sub-model as a segment (adapters/colmap_segments.h),
// leave out those that only repeat images of a larger one, associate with
// the odometry, calibrate with the stretch check
// (solver/stretch_consistency.h: odometry as the witness of COLMAP), align
// each sub-model into the odometry origin frame in metres
// (solver/similarity_alignment.h).
#pragma once

#include "odomcal/adapters/association.h"
#include "odomcal/adapters/colmap_model.h"
#include "odomcal/adapters/colmap_segments.h"
#include "odomcal/adapters/image_timestamps.h"
#include "odomcal/adapters/robot_description.h"
#include "odomcal/adapters/systematics_estimation.h"
#include "odomcal/adapters/timestamp.h"
#include "odomcal/adapters/trajectory.h"
#include "odomcal/adapters/trajectory_io.h"
#include "odomcal/plugin/colmap/image_coverage.h"
#include "odomcal/plugin/colmap/joint_adjustment_run.h"
#include "odomcal/plugin/colmap/mapper_attempts.h"
#include "odomcal/solver/calibration_options.h"
#include "odomcal/solver/floor_plane.h"
#include "odomcal/solver/repeatability.h"
#include "odomcal/solver/similarity_alignment.h"
#include "odomcal/solver/stretch_consistency.h"

#include <cstdint>
#include <functional>
#include <map>
#include <optional>
#include <set>
#include <string>
#include <utility>
#include <vector>

namespace odomcal {

struct ColmapCalibrationInputs {
  std::string model_path;     // a model folder or the mapper's sparse root
  std::string database_path;  // optional: counts unregistered images
  std::string odometry_path;
  OdometryFormat odometry_format = OdometryFormat::kAuto;
  TimeUnit odometry_time_unit = TimeUnit::kSeconds;
  bool odometry_time_unit_given = false;  // by the user, not the default
  std::string image_timestamps_path;  // CSV image_name,timestamp; else names
  TimeUnit image_time_unit = TimeUnit::kSeconds;  // of the CSV
  std::optional<TimeUnit> file_name_time_unit;    // of numeric file names
  AssociationOptions association;
  CalibrationOptions calibration;
  StretchOptions stretch;
  // Clock offset and odometry intrinsics estimated with the extrinsic.
  SystematicsEstimationOptions systematics;
  // The frames the robot outputs name (robot_description.h).
  RobotFrameNames robot_frames;
  // Translation z from the floor under the metric model (floor_height.h).
  FloorPlaneOptions floor;
  // One adjustment of images, odometry and extrinsic after the two-step
  // calibration (joint_adjustment_stage.h).
  JointAdjustmentSettings joint_adjustment;
  // One camera of a rig: only the images of these COLMAP cameras (empty:
  // every image; colmap_cameras.h).
  std::set<uint32_t> camera_ids;

  // Throws std::invalid_argument naming the flag of the first bad option.
  void Check() const;
};

// A point of a COLMAP reconstruction: its model folder and point3D id, the
// same for every camera whose images see it.
using ReconstructionPoint = std::pair<std::string, int64_t>;

// One sub-model in metres in the odometry's origin frame.
struct MetricSubModel {
  // Folder name: the sub-model's ("0", "1", ...), or "<sub-model>_<part>"
  // when the checks cut the sub-model into parts with scales of their own.
  std::string name;
  int output_segment = -1;  // segment whose scale was used
  // The similarity that moved the sub-model into metres; absent for the
  // joint adjustment's model, whose every pose and point was adjusted.
  std::optional<Sim3d> origin_from_sfm;
  ColmapModel model;  // transformed copy
  // The joint adjustment's model numbers its points anew: per point3D id,
  // the reconstruction's point it is. Empty for a transformed copy, whose
  // ids are the reconstruction's.
  std::map<int64_t, ReconstructionPoint> reconstruction_points;
};

struct ColmapCalibrationRun {
  std::vector<ColmapSegment> segments;  // one per sub-model, but for:
  std::vector<DuplicateSegment> duplicate_segments;  // left out
  Trajectory odometry;
  int num_database_images = -1;  // -1: no database given
  // The database's cameras by camera id: the intrinsics before COLMAP's
  // bundle adjustment (the floor and the joint adjustment compare); empty
  // without a database or from a cameras table the run cannot read.
  std::map<uint32_t, ColmapCamera> database_cameras;
  AssociationResult association;  // the motion pairs and their counts
  StretchCheckResult check;       // result, pairs used, stretches
  std::vector<MetricSubModel> metric_models;
  // `odomcal run` only: every mapper run and the one calibrated here.
  std::vector<MapperAttempt> mapper_attempts;
  int chosen_mapper_attempt = -1;
  // The COLMAP that reconstructed the model ("4.1.1", from its banner), for
  // `odomcal run`; empty for a project calibrated as given.
  std::string colmap_version;
  // The program that mapped it: "mapper" (incremental), "global_mapper"
  // (COLMAP's, from 4.0) or "glomap mapper" (the standalone GLOMAP).
  std::string colmap_mapper;
  // `odomcal run` only: how many of the images selected for COLMAP are in
  // the calibration, per stretch of the drive (image_coverage.h).
  std::optional<ImageCoverage> coverage;
  // The clock offset and odometry intrinsics used; `odometry` above is the
  // odometry corrected with them (what the metric models are aligned to).
  SystematicsEstimate systematics;
  // The calibration repeated on time blocks of the drive (ran = false when
  // it did not succeed).
  Repeatability repeatability;
  // The joint adjustment (--joint_adjustment on): what it did, and the
  // two-step extrinsic it started from.
  JointAdjustmentRun joint;
};

// What a long step is doing (the joint adjustment's passes and re-solves),
// for a progress display: a short line, called on the calling thread.
using CalibrationProgress = std::function<void(const std::string& message)>;

// Throws FormatError (unreadable inputs) or std::invalid_argument (options).
// Reads only; the outputs are written by colmap_calibration_outputs.h.
ColmapCalibrationRun CalibrateColmapProject(
    const ColmapCalibrationInputs& inputs,
    const CalibrationProgress& progress = {});

}  // namespace odomcal
