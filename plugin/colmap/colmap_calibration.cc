// See the header for the steps. Metric models are exported per output
// segment: a sub-model cut by the stretch or scale checks into parts at
// different scales has no single correct similarity, so each part gets its
// own, and a folded stretch is not exported at all.

#include "odomcal/plugin/colmap/colmap_calibration.h"

#include "odomcal/adapters/colmap_database.h"
#include "odomcal/adapters/colmap_model_subset.h"
#include "odomcal/adapters/format_error.h"
#include "odomcal/adapters/input_plausibility.h"
#include "odomcal/adapters/odometry_interpolation_error.h"
#include "odomcal/adapters/systematics_warnings.h"
#include "odomcal/plugin/colmap/floor_height.h"
#include "odomcal/plugin/colmap/joint_adjustment_stage.h"
#include "odomcal/plugin/colmap/odometry_inputs.h"
#include "odomcal/plugin/colmap/scale_drift_warning.h"
#include "odomcal/solver/angles.h"
#include "odomcal/solver/format_number.h"
#include "odomcal/solver/noise_estimation.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <map>
#include <set>

namespace odomcal {
namespace {

namespace fs = std::filesystem;

// Ends included: an image at the end of a stretch left out that no pair
// of the calibration confirms is part of the fold. Measured on `small`
// seed 1: a fold up to the model's last image left that image (0.5 m off)
// in the metric model, bending its alignment by 3 cm and its size by 1.4 %.
bool InDroppedStretch(const StretchCheckResult& check,
                      int input_segment,
                      int64_t stamp_ns) {
  for (const InconsistentStretch& run : check.stretches) {
    if (!run.kept_as_segment && run.input_segment == input_segment &&
        stamp_ns >= run.first_stamp_ns && stamp_ns <= run.last_stamp_ns) {
      return true;
    }
  }
  return false;
}

// The output segments an image of input segment `input` at `stamp_ns`
// (odometry clock) belongs to: those whose motion pairs span it, else the
// nearest in time (images before the first or after the last keyframe)
// unless a dropped stretch is nearer; none inside a dropped stretch unless
// a pair of the calibration confirms it (`confirmed`: the image at a
// stretch's end shared with the pair next to it).
std::vector<int> OutputSegmentsOfImage(
    const StretchCheckResult& check,
    const std::vector<std::pair<int64_t, int64_t>>& spans,
    int input,
    int64_t stamp_ns,
    bool confirmed) {
  if (!confirmed && InDroppedStretch(check, input, stamp_ns)) return {};
  std::vector<int> inside;
  int nearest = -1;
  int64_t nearest_distance = std::numeric_limits<int64_t>::max();
  for (size_t output = 0; output < spans.size(); ++output) {
    if (check.input_segment_of_output_segment[output] != input) continue;
    const auto [first, last] = spans[output];
    if (first > last) continue;  // no pairs
    if (stamp_ns >= first && stamp_ns <= last)
      inside.push_back(static_cast<int>(output));
    const int64_t distance =
        stamp_ns < first ? first - stamp_ns : stamp_ns - last;
    if (distance < nearest_distance) {
      nearest_distance = distance;
      nearest = static_cast<int>(output);
    }
  }
  if (inside.empty() && nearest >= 0) {
    // Past a dropped stretch at the end (or before one at the start), the
    // image is nearer the fold than any segment: it goes with the fold.
    for (const InconsistentStretch& run : check.stretches) {
      if (run.kept_as_segment || run.input_segment != input) continue;
      const int64_t distance = stamp_ns < run.first_stamp_ns
                                   ? run.first_stamp_ns - stamp_ns
                                   : stamp_ns - run.last_stamp_ns;
      if (distance < nearest_distance) return {};
    }
    inside.push_back(nearest);
  }
  return inside;
}

// Time span (odometry clock) of each output segment's motion pairs.
std::vector<std::pair<int64_t, int64_t>> SegmentSpans(
    const StretchCheckResult& check) {
  std::vector<std::pair<int64_t, int64_t>> spans(
      check.input_segment_of_output_segment.size(),
      {std::numeric_limits<int64_t>::max(),
       std::numeric_limits<int64_t>::min()});
  for (const MotionPair& pair : check.pairs) {
    auto& [first, last] = spans.at(pair.segment);
    first = std::min(first, pair.stamp_i_ns);
    last = std::max(last, pair.stamp_j_ns);
  }
  return spans;
}

ColmapModel TransformModel(const ColmapModel& model,
                           const Sim3d& origin_from_sfm) {
  ColmapModel metric = model;
  for (auto& [id, image] : metric.images) {
    image.cam_from_world = CamFromOrigin(image.cam_from_world, origin_from_sfm);
  }
  for (auto& [id, point] : metric.points3D) {
    point.xyz = origin_from_sfm * point.xyz;
  }
  return metric;
}

// "a, b, c" for up to 8 names, else the first and last 3 around "...".
std::string NameList(const std::vector<std::string>& names) {
  constexpr size_t kMaxListed = 8, kEnds = 3;
  std::string list;
  for (size_t i = 0; i < names.size(); ++i) {
    if (names.size() > kMaxListed && i >= kEnds && i + kEnds < names.size()) {
      if (i == kEnds) list += ", ...";
      continue;
    }
    list += (list.empty() ? "" : ", ") + names[i];
  }
  return list;
}

bool HasUsableExtrinsic(const CalibrationResult& result) {
  return result.has_estimate && result.observability.ExtrinsicDetermined();
}

// For image `index` of `segment` that no motion pair holds (it lies between
// keyframes): whether the odometry contradicts its motion from each of the
// nearest images before and after it that a non-contradicting pair of output
// segment `output` holds. A reference counts only within one keyframe step
// (the odometry motion from it below twice the keyframe thresholds), so that
// drift or a wheel slip over a longer span is not read as a misregistration;
// without one, nothing is judged (false). The pair is built as association
// builds its pairs (with the odometry's interpolation covariance) and judged
// as the check judges its own (ContradictsOdometry), and, when the fit
// estimated the noise, under that noise too: a pair the fit used is never
// contradicted. Measured on the rendered 1 000-image drive: 000194.png,
// registered 106 deg off between two keyframes, was exported.
bool ContradictedBetweenKeyframes(
    const ColmapSegment& segment,
    size_t index,
    int output,
    const std::set<std::pair<int, int64_t>>& confirmed,
    int64_t camera_time_offset_ns,
    const ColmapCalibrationRun& run,
    const ColmapCalibrationInputs& inputs) {
  const std::vector<StampedPose>& poses = segment.trajectory.poses;
  const CalibrationResult& fit = run.check.result;
  const double gap_s = run.association.max_odometry_gap_s;
  const int64_t stamp = poses[index].stamp_ns + camera_time_offset_ns;
  const auto origin_from_odom =
      InterpolateOdometry(run.odometry, stamp, gap_s, nullptr);
  if (!origin_from_odom) return false;
  const Eigen::Matrix3d interpolation =
      OdometryInterpolationCovariance(run.odometry, stamp);
  CalibrationOptions estimated = inputs.calibration;
  if (fit.noise_estimate) estimated.noise = fit.noise_estimate->noise;
  int num_references = 0;
  for (const long step : {-1L, 1L}) {
    long reference = -1;
    for (long j = static_cast<long>(index) + step;
         j >= 0 && j < static_cast<long>(poses.size());
         j += step) {
      if (confirmed.count(
              {output, poses[j].stamp_ns + camera_time_offset_ns}) != 0) {
        reference = j;
        break;
      }
    }
    if (reference < 0) continue;
    const int64_t stamp_ref = poses[reference].stamp_ns + camera_time_offset_ns;
    const auto origin_from_odom_ref =
        InterpolateOdometry(run.odometry, stamp_ref, gap_s, nullptr);
    if (!origin_from_odom_ref) continue;
    MotionPair pair;
    pair.odom_i_from_odom_j =
        Inverse(*origin_from_odom_ref) * *origin_from_odom;
    if (RotationAngle(pair.odom_i_from_odom_j.rotation) >=
            2.0 * run.association.keyframe_min_rotation_deg * kDegToRad ||
        pair.odom_i_from_odom_j.translation.norm() >=
            2.0 * run.association.keyframe_min_translation_m) {
      continue;
    }
    pair.cam_i_from_cam_j = Inverse(poses[reference].world_from_sensor) *
                            poses[index].world_from_sensor;
    pair.segment = output;
    pair.stamp_i_ns = stamp_ref;
    pair.stamp_j_ns = stamp;
    const Eigen::Matrix3d interpolation_ref =
        OdometryInterpolationCovariance(run.odometry, stamp_ref);
    if (!interpolation_ref.isZero(0.0) || !interpolation.isZero(0.0)) {
      pair.odom_interpolation_covariance =
          RelativeMotionInterpolationCovariance(*origin_from_odom_ref,
                                                interpolation_ref,
                                                *origin_from_odom,
                                                interpolation);
    }
    ++num_references;
    if (!ContradictsOdometry(pair, false, fit, inputs.calibration)) {
      return false;
    }
    if (fit.noise_estimate &&
        !ContradictsOdometry(ScaleCovariances({pair}, *fit.noise_estimate)[0],
                             false,
                             fit,
                             estimated)) {
      return false;
    }
  }
  return num_references > 0;
}

// The database's cameras by camera id; none from a cameras table it cannot
// read (the floor then compares with square pixels and the joint adjustment
// holds the intrinsics; the images table, which the run needs, was read).
std::map<uint32_t, ColmapCamera> DatabaseCameras(
    const std::string& database_path) {
  std::map<uint32_t, ColmapCamera> cameras;
  std::vector<ColmapDatabaseCamera> rows;
  try {
    rows = ReadColmapDatabaseCameras(database_path);
  } catch (const FormatError&) {
    return cameras;
  }
  for (const ColmapDatabaseCamera& row : rows) {
    cameras[row.camera.camera_id] = row.camera;
  }
  return cameras;
}

}  // namespace

void ColmapCalibrationInputs::Check() const {
  association.Check();
  calibration.Check();
  robot_frames.Check();
  floor.Check();
  joint_adjustment.Check();
}

ColmapCalibrationRun CalibrateColmapProject(
    const ColmapCalibrationInputs& inputs,
    const CalibrationProgress& progress) {
  inputs.Check();
  const ImageTimestamps timestamps =
      inputs.image_timestamps_path.empty()
          ? ImageTimestamps::FromFileNames(inputs.file_name_time_unit)
          : ImageTimestamps::FromCsv(inputs.image_timestamps_path,
                                     inputs.image_time_unit);
  ColmapCalibrationRun run;
  ColmapSegmentOptions segment_options;
  segment_options.camera_ids = inputs.camera_ids;
  run.segments =
      ReadColmapSegments(inputs.model_path, timestamps, segment_options);
  if (run.segments.empty()) {
    throw FormatError(inputs.model_path + ": no COLMAP model found");
  }
  run.duplicate_segments = RemoveDuplicateSegments(&run.segments);
  if (!inputs.database_path.empty()) {
    run.num_database_images = 0;
    for (const ColmapDatabaseImage& image :
         ReadColmapDatabaseImages(inputs.database_path)) {
      const bool counted = inputs.camera_ids.empty() ||
                           inputs.camera_ids.count(image.camera_id) != 0;
      run.num_database_images += counted ? 1 : 0;
    }
    run.database_cameras = DatabaseCameras(inputs.database_path);
  }
  run.odometry = ReadOdometryOf(inputs);
  CheckOdometrySpeed(run.odometry);

  std::vector<Trajectory> cameras;
  std::vector<int64_t> image_stamps_ns;
  for (const ColmapSegment& segment : run.segments) {
    cameras.push_back(segment.trajectory);
    for (const StampedPose& pose : segment.trajectory.poses) {
      image_stamps_ns.push_back(pose.stamp_ns);
    }
  }
  if (inputs.image_timestamps_path.empty()) {
    CheckImageTimesAreNotFrameNumbers(
        image_stamps_ns, inputs.model_path, timestamps.how_read());
  }
  // The association and calibration, once or in the systematics loop.
  const auto calibrate = [&](const AssociationResult& association) {
    if (association.num_usable_camera_poses == 0) {
      throw FormatError(
          inputs.model_path +
          ": no registered image time falls inside the "
          "odometry " +
          inputs.odometry_path + " (" +
          std::to_string(association.num_outside_odometry_span) +
          " outside its span, " +
          std::to_string(association.num_in_odometry_gaps) + " in gaps): " +
          TimeSpansText(cameras,
                        timestamps.how_read(),
                        association.camera_time_offset_ns,
                        run.odometry,
                        association.camera_time_offset_ns !=
                            inputs.association.camera_time_offset_ns) +
          "; check the image timestamps, their unit and "
          "--camera_time_offset_s");
    }
    CheckRotationAngleUnits(association.pairs, run.odometry.source);
    run.check = CalibrateWithStretchCheck(
        association.pairs, inputs.calibration, inputs.stretch);
    return std::make_pair(&run.check.pairs, &run.check.result);
  };
  run.systematics = EstimateSystematics(cameras,
                                        run.odometry,
                                        inputs.association,
                                        inputs.calibration,
                                        inputs.systematics,
                                        calibrate,
                                        &run.association);
  // From here on: the odometry corrected with the estimated intrinsics, and
  // the estimated clock offset.
  run.odometry = run.systematics.corrected_odometry;
  const int64_t camera_time_offset_ns = run.systematics.camera_time_offset_ns;
  AddSystematicsWarnings(run.systematics, &run.check.result);
  CalibrationResult& result = run.check.result;
  run.repeatability = CheckRepeatability(
      run.check.pairs, result, inputs.calibration, RepeatabilityOptions());
  if (const std::string warning = RepeatabilityWarning(run.repeatability);
      !warning.empty()) {
    result.warnings.push_back(warning);
  }
  if (result.status == CalibrationStatus::kSuccess) {
    if (const auto warning = ExtrinsicDistanceWarning(result.odom_from_cam)) {
      result.warnings.push_back(*warning);
    }
  }
  for (const DuplicateSegment& duplicate : run.duplicate_segments) {
    result.warnings.push_back(
        "sub-model " + duplicate.segment.sub_model + " (" +
        std::to_string(duplicate.segment.image_names.size()) +
        " images) holds no image that sub-model " + duplicate.duplicate_of +
        " does not: left out as a second reconstruction of the same images");
  }
  for (const InconsistentStretch& stretch : run.check.stretches) {
    result.warnings.push_back(
        "sub-model " + run.segments[stretch.input_segment].sub_model +
        ": a stretch of " + std::to_string(stretch.num_pairs) +
        " motion pairs (" + FormatTimestampSeconds(stretch.first_stamp_ns) +
        " .. " + FormatTimestampSeconds(stretch.last_stamp_ns) +
        " s) contradicts the odometry: " +
        (stretch.kept_as_segment
             ? "kept as a separate segment with its own scale"
             : "left out (COLMAP likely folded it)"));
  }
  for (const ScaleChangeCut& cut : run.check.scale_changes) {
    result.warnings.push_back(
        "sub-model " + run.segments[cut.input_segment].sub_model +
        ": its metric scale changes by " +
        SignedPercent(cut.scale_after / cut.scale_before - 1.0) + " at " +
        FormatTimestampSeconds(cut.stamp_ns) +
        " s (COLMAP scale drift, seen in the step lengths): the parts are "
        "calibrated as segments with scales of their own");
  }
  for (const ScaleDrift& drift : run.check.scale_drifts) {
    result.warnings.push_back(ScaleDriftWarning(
        run.segments[drift.input_segment].sub_model, drift, result));
  }
  if (run.association.num_outside_odometry_span +
          run.association.num_in_odometry_gaps >
      0) {
    result.warnings.push_back(
        std::to_string(run.association.num_outside_odometry_span +
                       run.association.num_in_odometry_gaps) +
        " registered images lie outside the odometry span or in its gaps");
  }
  if (!HasUsableExtrinsic(result)) {
    return run;
  }

  // Metric models in the odometry origin frame, one per output segment: the
  // images of its sub-model within its time span (a folded stretch left out
  // and a part at another scale are not carried along).
  const std::vector<std::pair<int64_t, int64_t>> spans =
      SegmentSpans(run.check);
  std::map<int, int> num_parts;
  for (const int input : run.check.input_segment_of_output_segment)
    ++num_parts[input];
  std::map<int, int> next_part;
  std::map<int, ColmapModel> models;  // read once per sub-model
  // (output segment, stamp) of the images in a pair the odometry
  // contradicts (ContradictsOdometry), and in any other: an image only in
  // contradicted pairs is misregistered (it spoils both its pairs), so it is
  // left out of the metric model, whose alignment it would bend too.
  // Measured on `small` seed 2: the last image 97 mm off made the model's
  // scale 0.42 % wrong. A pair beyond only the estimated noise (tenths of a
  // degree) does not make its images wrong by that much.
  std::set<std::pair<int, int64_t>> confirmed, contradicted;
  // (input segment, stamp) of the images in a pair that does not contradict.
  std::set<std::pair<int, int64_t>> confirmed_in_input;
  const std::vector<char>& contradicts = run.check.contradicts_odometry;
  for (size_t p = 0; p < run.check.pairs.size(); ++p) {
    const MotionPair& pair = run.check.pairs[p];
    const bool contradicting = p < contradicts.size() && contradicts[p] != 0;
    auto& images = contradicting ? contradicted : confirmed;
    images.insert({pair.segment, pair.stamp_i_ns});
    images.insert({pair.segment, pair.stamp_j_ns});
    if (!contradicting) {
      const int input =
          run.check.input_segment_of_output_segment.at(pair.segment);
      confirmed_in_input.insert({input, pair.stamp_i_ns});
      confirmed_in_input.insert({input, pair.stamp_j_ns});
    }
  }
  for (size_t output = 0; output < spans.size(); ++output) {
    const int k = run.check.input_segment_of_output_segment[output];
    const int part = next_part[k]++;
    const ColmapSegment& segment = run.segments.at(k);
    if (!(result.metric_scales.at(output) > 0.0)) continue;
    std::vector<Rigid3d> origin_from_cam, sfm_from_cam;
    std::set<std::string> names;
    std::vector<std::string> left_out;
    std::vector<std::string> left_out_between_keyframes;
    // Images without odometry at their (offset-shifted) time: no pose for
    // the alignment, so not exported; named, since the offset (when
    // estimated) can move images out that the user expects in.
    std::vector<std::string> outside_span, in_gaps;
    for (size_t i = 0; i < segment.trajectory.poses.size(); ++i) {
      const StampedPose& pose = segment.trajectory.poses[i];
      const int64_t stamp = pose.stamp_ns + camera_time_offset_ns;
      const std::vector<int> owners =
          OutputSegmentsOfImage(run.check,
                                spans,
                                k,
                                stamp,
                                confirmed_in_input.count({k, stamp}) != 0);
      if (std::find(owners.begin(), owners.end(), static_cast<int>(output)) ==
          owners.end()) {
        continue;
      }
      const std::pair<int, int64_t> key(static_cast<int>(output), stamp);
      if (contradicted.count(key) != 0 && confirmed.count(key) == 0) {
        left_out.push_back(segment.image_names.at(i));
        continue;
      }
      if (contradicted.count(key) == 0 && confirmed.count(key) == 0 &&
          ContradictedBetweenKeyframes(segment,
                                       i,
                                       static_cast<int>(output),
                                       confirmed,
                                       camera_time_offset_ns,
                                       run,
                                       inputs)) {
        left_out_between_keyframes.push_back(segment.image_names.at(i));
        continue;
      }
      InterpolationFailure why;
      const auto origin_from_odom = InterpolateOdometry(
          run.odometry, stamp, run.association.max_odometry_gap_s, &why);
      if (!origin_from_odom) {
        (why == InterpolationFailure::kInGap ? in_gaps : outside_span)
            .push_back(segment.image_names.at(i));
        continue;
      }
      origin_from_cam.push_back(*origin_from_odom * result.odom_from_cam);
      sfm_from_cam.push_back(pose.world_from_sensor);
      names.insert(segment.image_names.at(i));
    }
    if (origin_from_cam.empty()) continue;
    if (models.count(k) == 0)
      models.emplace(k, ReadColmapModel(segment.model_path));
    const ColmapModel& model = models.at(k);
    std::set<uint32_t> image_ids;
    for (const auto& [id, image] : model.images) {
      if (names.count(image.name) != 0) image_ids.insert(id);
    }
    MetricSubModel metric;
    metric.name =
        segment.sub_model.empty() ? std::to_string(k) : segment.sub_model;
    if (num_parts[k] > 1) metric.name += "_" + std::to_string(part);
    metric.output_segment = static_cast<int>(output);
    metric.origin_from_sfm = AlignSfmToOrigin(
        origin_from_cam, sfm_from_cam, result.metric_scales[output]);
    metric.model = TransformModel(ColmapModelSubset(model, image_ids),
                                  *metric.origin_from_sfm);
    if (!left_out.empty()) {
      std::string list;
      for (const std::string& name : left_out)
        list += (list.empty() ? "" : ", ") + name;
      result.warnings.push_back(
          "sparse_metric/" + metric.name + ": left out " +
          std::to_string(left_out.size()) +
          (left_out.size() == 1 ? " image" : " images") +
          " whose every motion pair the odometry contradicts (" + list + ")");
    }
    if (!left_out_between_keyframes.empty()) {
      result.warnings.push_back(
          "sparse_metric/" + metric.name + ": left out " +
          std::to_string(left_out_between_keyframes.size()) +
          (left_out_between_keyframes.size() == 1 ? " image" : " images") +
          " between keyframes whose motion from the nearest keyframe the "
          "odometry contradicts (" +
          NameList(left_out_between_keyframes) + ")");
    }
    // "estimated" whenever the offset used is not the one given (also a
    // coarse peak the refinement did not move).
    const std::string offset_text =
        std::string(camera_time_offset_ns !=
                            inputs.association.camera_time_offset_ns
                        ? "estimated"
                        : "given") +
        " camera time offset " +
        FormatNumber(NsToSeconds(camera_time_offset_ns)) + " s";
    for (const auto& [skipped, where] :
         {std::make_pair(&outside_span, "outside the odometry span"),
          std::make_pair(&in_gaps, "in gaps of the odometry")}) {
      if (skipped->empty()) continue;
      result.warnings.push_back("sparse_metric/" + metric.name + ": left out " +
                                std::to_string(skipped->size()) +
                                (skipped->size() == 1 ? " image" : " images") +
                                " whose time lies " + where + " at the " +
                                offset_text + " (" + NameList(*skipped) + ")");
    }
    run.metric_models.push_back(std::move(metric));
  }
  std::map<std::string, int64_t> stamp_of_image;
  for (const ColmapSegment& segment : run.segments) {
    for (size_t i = 0; i < segment.trajectory.poses.size(); ++i) {
      stamp_of_image.emplace(segment.image_names.at(i),
                             segment.trajectory.poses[i].stamp_ns);
    }
  }
  // Before the floor: the floor is fitted in the adjusted model.
  std::optional<MetricSubModel> agreeing_joint_model;
  ApplyJointAdjustment(
      inputs, stamp_of_image, progress, &run, &agreeing_joint_model);
  ApplyFloorPlane(inputs.floor,
                  inputs.calibration.max_translation_stddev_m,
                  stamp_of_image,
                  agreeing_joint_model ? &*agreeing_joint_model : nullptr,
                  &run);
  return run;
}

}  // namespace odomcal
