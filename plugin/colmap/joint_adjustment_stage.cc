#include "odomcal/plugin/colmap/joint_adjustment_stage.h"

#include "odomcal/adapters/association.h"
#include "odomcal/adapters/odometry_increments.h"
#include "odomcal/adapters/odometry_interpolation_error.h"
#include "odomcal/plugin/colmap/joint_input.h"
#include "odomcal/solver/angles.h"
#include "odomcal/solver/format_number.h"
#include "odomcal/solver/hand_eye_residual.h"
#include "odomcal/solver/joint_extrinsic.h"
#include "odomcal/solver/noise_estimation.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <numeric>
#include <optional>
#include <set>
#include <stdexcept>
#include <thread>
#include <utility>

namespace odomcal {
namespace {

// Stretches of at least this many images, at most kMaxStretchesPerPart per
// part of the two-step model, for the scale comparison.
constexpr int kMinStretchImages = 10;
constexpr int kMaxStretchesPerPart = 10;

// The adjustment holds one pose per component where it started: its
// placement in the origin frame is a choice of gauge. Placed as the
// two-step places its models, by the planar motion that best aligns the
// robot's positions with the odometry's at the image times (least squares;
// the extrinsic and the model's shape are unchanged by it).
void AlignWithOdometry(const ColmapCalibrationRun& run,
                       const JointInput& input,
                       JointAdjustmentResult* result) {
  std::vector<Eigen::Vector2d> adjusted, odometry;
  for (size_t i = 0; i < result->origin_from_odom.size(); ++i) {
    const auto origin_from_odom =
        InterpolateOdometry(run.odometry,
                            input.image_stamps_ns[i],
                            run.association.max_odometry_gap_s,
                            nullptr);
    if (!origin_from_odom) continue;
    adjusted.push_back(result->origin_from_odom[i].translation.head<2>());
    odometry.push_back(origin_from_odom->translation.head<2>());
  }
  if (adjusted.size() < 2) return;
  Eigen::Vector2d mean_adjusted = Eigen::Vector2d::Zero();
  Eigen::Vector2d mean_odometry = Eigen::Vector2d::Zero();
  for (size_t k = 0; k < adjusted.size(); ++k) {
    mean_adjusted += adjusted[k];
    mean_odometry += odometry[k];
  }
  mean_adjusted /= static_cast<double>(adjusted.size());
  mean_odometry /= static_cast<double>(adjusted.size());
  double dot = 0.0, cross = 0.0;
  for (size_t k = 0; k < adjusted.size(); ++k) {
    const Eigen::Vector2d a = adjusted[k] - mean_adjusted;
    const Eigen::Vector2d b = odometry[k] - mean_odometry;
    dot += a.dot(b);
    cross += a.x() * b.y() - a.y() * b.x();
  }
  const double yaw = std::atan2(cross, dot);
  const Eigen::Rotation2Dd rotation(yaw);
  const Eigen::Vector2d shift = mean_odometry - rotation * mean_adjusted;
  const Rigid3d placement = PlanarPose{shift.x(), shift.y(), yaw}.ToRigid3d();
  for (Rigid3d& pose : result->origin_from_odom) pose = placement * pose;
  for (Eigen::Vector3d& point : result->points) point = placement * point;
}

Eigen::Vector3d CentreOf(const Rigid3d& origin_from_odom,
                         const Rigid3d& odom_from_cam) {
  return (origin_from_odom * odom_from_cam).translation;
}

// The two-step scale and the adjusted model's, per stretch of each part.
void CompareScales(const ColmapCalibrationRun& run,
                   const JointInput& input,
                   JointAdjustmentRun* joint) {
  std::map<std::string, int> image_index;
  for (size_t i = 0; i < input.image_names.size(); ++i) {
    image_index.emplace(input.image_names[i], static_cast<int>(i));
  }
  const JointAdjustmentResult& result = joint->result;
  for (const MetricSubModel& metric : run.metric_models) {
    // (stamp, joint image, two-step centre) in time order.
    std::vector<std::tuple<int64_t, int, Eigen::Vector3d>> images;
    for (const auto& [id, image] : metric.model.images) {
      const auto i = image_index.find(image.name);
      if (i == image_index.end()) continue;
      images.emplace_back(input.image_stamps_ns[i->second],
                          i->second,
                          Inverse(image.cam_from_world).translation);
    }
    std::sort(images.begin(), images.end(), [](const auto& a, const auto& b) {
      return std::get<0>(a) < std::get<0>(b);
    });
    const int n = static_cast<int>(images.size());
    if (n < 2 || !metric.origin_from_sfm) continue;
    const double scale = metric.origin_from_sfm->scale;
    const int num_stretches =
        std::clamp(n / kMinStretchImages, 1, kMaxStretchesPerPart);
    for (int s = 0; s < num_stretches; ++s) {
      const int first = s * (n - 1) / num_stretches;
      const int last = (s + 1) * (n - 1) / num_stretches;
      double two_step_length = 0.0;
      double joint_length = 0.0;
      for (int k = first; k < last; ++k) {
        two_step_length +=
            (std::get<2>(images[k + 1]) - std::get<2>(images[k])).norm();
        joint_length +=
            (CentreOf(result.origin_from_odom[std::get<1>(images[k + 1])],
                      result.odom_from_cam) -
             CentreOf(result.origin_from_odom[std::get<1>(images[k])],
                      result.odom_from_cam))
                .norm();
      }
      if (!(two_step_length > 0.0)) continue;
      JointStretchScale stretch;
      stretch.metric_model = metric.name;
      stretch.first_stamp_ns = std::get<0>(images[first]);
      stretch.last_stamp_ns = std::get<0>(images[last]);
      stretch.num_images = last - first + 1;
      stretch.path_length_m = joint_length;
      stretch.two_step_scale = scale;
      stretch.joint_scale = scale * joint_length / two_step_length;
      joint->max_scale_change = std::max(
          joint->max_scale_change,
          std::abs(stretch.joint_scale / stretch.two_step_scale - 1.0));
      joint->stretches.push_back(stretch);
    }
  }
}

// The adjusted model as one COLMAP model: cameras numbered from 1 in the
// problem's order, images likewise, points numbered from 1 (the
// reconstruction's point each one is into *reconstruction_points); an
// observation the adjustment did not use is no longer a point's, a point seen
// in fewer than two images is left out.
ColmapModel AdjustedModel(
    const JointInput& input,
    const JointAdjustmentResult& result,
    std::map<int64_t, ReconstructionPoint>* reconstruction_points) {
  ColmapModel model;
  for (size_t c = 0; c < input.source_cameras.size(); ++c) {
    ColmapCamera camera = *input.source_cameras[c];
    camera.camera_id = static_cast<uint32_t>(c + 1);
    camera.params = result.cameras[c].params;
    model.cameras.emplace(camera.camera_id, camera);
  }
  for (size_t i = 0; i < input.source_images.size(); ++i) {
    ColmapImage image = *input.source_images[i];
    image.image_id = static_cast<uint32_t>(i + 1);
    image.camera_id = static_cast<uint32_t>(input.problem.images[i].camera + 1);
    image.cam_from_world =
        Inverse(result.origin_from_odom[i] * result.odom_from_cam);
    for (ColmapPoint2D& point2D : image.points2D) {
      point2D.point3D_id = kColmapNoPoint3D;
    }
    model.images.emplace(image.image_id, std::move(image));
  }
  // Per point, its used observations (at most one per image).
  std::vector<std::vector<size_t>> observations_of(input.problem.points.size());
  for (size_t k = 0; k < input.problem.observations.size(); ++k) {
    if (result.observation_error_px[k] < 0.0) continue;
    observations_of[input.problem.observations[k].point].push_back(k);
  }
  int64_t next_id = 1;
  for (size_t p = 0; p < observations_of.size(); ++p) {
    ColmapPoint3D point;
    double error_sum = 0.0;
    std::set<int> images;
    for (const size_t k : observations_of[p]) {
      const JointObservation& observation = input.problem.observations[k];
      ColmapImage& image = model.images.at(observation.image + 1);
      ColmapPoint2D& point2D = image.points2D.at(input.observation_point2D[k]);
      if (point2D.point3D_id != kColmapNoPoint3D) continue;  // taken
      point2D.point3D_id = next_id;
      point.track.push_back({image.image_id, input.observation_point2D[k]});
      error_sum += result.observation_error_px[k];
      images.insert(observation.image);
    }
    if (images.size() < 2) {
      for (const ColmapTrackElement& element : point.track) {
        model.images.at(element.image_id)
            .points2D[element.point2D_idx]
            .point3D_id = kColmapNoPoint3D;
      }
      continue;
    }
    if (input.reconstruction_points[p]) {
      reconstruction_points->emplace(next_id, *input.reconstruction_points[p]);
    }
    point.point3D_id = next_id++;
    point.xyz = result.points[p];
    point.rgb = input.source_points[p]->rgb;
    point.error = error_sum / static_cast<double>(point.track.size());
    model.points3D.emplace(point.point3D_id, std::move(point));
  }
  return model;
}

// The adjusted model as one metric model, "0", with the output segment of
// the two-step's first (run.metric_models is not empty).
MetricSubModel AdjustedMetricModel(const ColmapCalibrationRun& run,
                                   const JointInput& input,
                                   const JointAdjustmentResult& result) {
  MetricSubModel adjusted;
  adjusted.name = "0";
  adjusted.output_segment = run.metric_models.front().output_segment;
  adjusted.model =
      AdjustedModel(input, result, &adjusted.reconstruction_points);
  return adjusted;
}

// One progress line.
std::string JointProgressLine(const JointAdjustmentProgress& where,
                              double seconds,
                              const std::string& label) {
  std::string line = label + ": ";
  if (where.num_replicates > 0) {
    line += "jackknife re-solve " + std::to_string(where.replicate) + " of " +
            std::to_string(where.num_replicates);
  } else {
    line += "pass " + std::to_string(where.pass);
  }
  return line + ", iteration " + std::to_string(where.iteration) + ", " +
         FormatPrintf("%.0f s", seconds);
}

}  // namespace

JointAdjustmentOptions JointOptionsWithProgress(
    const JointAdjustmentSettings& settings,
    const CalibrationProgress& progress,
    const std::string& label) {
  JointAdjustmentOptions options = settings.options;
  options.refine_intrinsics = settings.intrinsics != JointIntrinsics::kHeld;
  options.num_threads =
      std::max(1, static_cast<int>(std::thread::hardware_concurrency()));
  if (progress) {
    const auto start = std::chrono::steady_clock::now();
    options.progress = [progress, start, label](
                           const JointAdjustmentProgress& where) {
      progress(JointProgressLine(where,
                                 std::chrono::duration<double>(
                                     std::chrono::steady_clock::now() - start)
                                     .count(),
                                 label));
    };
  }
  return options;
}

std::string ToString(JointIntrinsics intrinsics) {
  switch (intrinsics) {
    case JointIntrinsics::kHeld:
      return "held";
    case JointIntrinsics::kRefined:
      return "refined";
    case JointIntrinsics::kAuto:
      return "auto";
  }
  return "unknown";
}

JointIntrinsics JointIntrinsicsFromString(const std::string& name) {
  if (name == "held") return JointIntrinsics::kHeld;
  if (name == "refined") return JointIntrinsics::kRefined;
  if (name == "auto") return JointIntrinsics::kAuto;
  throw std::invalid_argument("joint_intrinsics: '" + name +
                              "' is not held, refined or auto");
}

std::string ToString(JointAdjustmentUse use) {
  switch (use) {
    case JointAdjustmentUse::kOn:
      return "on";
    case JointAdjustmentUse::kOff:
      return "off";
    case JointAdjustmentUse::kCheck:
      return "check";
  }
  return "off";
}

JointAdjustmentUse JointAdjustmentUseFromString(const std::string& name) {
  if (name == "on") return JointAdjustmentUse::kOn;
  if (name == "off") return JointAdjustmentUse::kOff;
  if (name == "check") return JointAdjustmentUse::kCheck;
  throw std::invalid_argument("joint_adjustment: '" + name +
                              "' is not on, off or check");
}

void ApplyJointAdjustment(const ColmapCalibrationInputs& inputs,
                          const std::map<std::string, int64_t>& stamp_of_image,
                          const CalibrationProgress& progress,
                          ColmapCalibrationRun* run,
                          std::optional<MetricSubModel>* agreeing_model) {
  if (agreeing_model) agreeing_model->reset();
  JointAdjustmentRun& joint = run->joint;
  CalibrationResult& result = run->check.result;
  if (inputs.joint_adjustment.use == JointAdjustmentUse::kOff) return;
  joint.requested = true;
  joint.use = inputs.joint_adjustment.use;
  joint.intrinsics = inputs.joint_adjustment.intrinsics;
  const bool check = joint.use == JointAdjustmentUse::kCheck;
  const std::string name =
      check ? "joint adjustment check" : "joint adjustment";
  // Where the check cannot run, the two-step result is what it would have
  // been without it: the console and the JSON say so, not a warning.
  const auto skip = [&](const std::string& why) {
    joint.skipped = why;
    if (!check) {
      result.warnings.push_back(name + " not run: " + why +
                                "; the two-step result stands");
    }
  };
  if (run->metric_models.empty() || !result.covariance) {
    skip("no metric model to adjust");
    return;
  }
  if (result.observability.translation_z == Determination::kEstimated) {
    skip(
        "it holds the extrinsic's z, which the SE(3) odometry's tilts "
        "determine here");
    return;
  }
  JointInput input;
  input.problem.odom_from_cam = result.odom_from_cam;
  if (const std::string why = AddMetricModels(
          *run, stamp_of_image, inputs.joint_adjustment.intrinsics, &input);
      !why.empty()) {
    skip(why);
    return;
  }
  AddOdometryLinks(inputs, *run, &input);
  AddOdometrySystematics(inputs, *run, /*refine_time_offset=*/true, &input);
  const JointAdjustmentOptions options = JointOptionsWithProgress(
      inputs.joint_adjustment, progress, "joint adjustment");
  joint.ran = true;
  joint.num_images = static_cast<int>(input.problem.images.size());
  joint.num_points = static_cast<int>(input.problem.points.size());
  joint.num_links = static_cast<int>(input.problem.links.size());
  joint.num_joining_links = input.num_joining_links;
  joint.refined_systematics = input.problem.systematics.has_value();
  joint.cameras_before = input.problem.cameras;
  joint.refine_intrinsics = options.refine_intrinsics;
  joint.two_step_odom_from_cam = result.odom_from_cam;
  joint.two_step_covariance = result.covariance->topLeftCorner<5, 5>();
  joint.result = AdjustJointly(input.problem, options);
  if (!joint.result.IsSuccess()) {
    if (!check) {
      result.warnings.push_back(
          name + " failed (" + ToString(joint.result.status) +
          "): " + joint.result.message + "; the two-step result stands");
    }
    return;
  }
  // Against the adjustment's covariance before any jackknife: the check
  // needs its estimate only where it contradicts. The quantities beyond the
  // threshold are the ones named.
  for (const ExtrinsicDisagreement& d :
       ExtrinsicDisagreements(joint.result.odom_from_cam,
                              joint.result.covariance,
                              joint.two_step_odom_from_cam,
                              joint.two_step_covariance,
                              0.0)) {
    joint.max_disagreement_sigmas =
        std::max(joint.max_disagreement_sigmas, d.Sigmas());
    if (d.Sigmas() > kJointContradictionSigmas) {
      joint.disagreements.push_back(d);
    }
  }
  const bool contradicted =
      joint.max_disagreement_sigmas > kJointContradictionSigmas;
  for (const ExtrinsicDisagreement& disagreement : joint.disagreements) {
    const bool angle =
        disagreement.quantity.find("translation") == std::string::npos;
    const std::string difference =
        angle ? FormatPrintf("%.3f deg", disagreement.difference)
              : FormatPrintf("%.1f mm", disagreement.difference * 1e3);
    result.warnings.push_back(
        name + ": " + disagreement.quantity +
        " differs from the two-step estimate by " + difference + " (" +
        FormatPrintf("%.1f", disagreement.Sigmas()) +
        " sigma of the difference): the motion pairs and the images "
        "disagree; "
        "check the reconstruction (scale drift, folds) and the odometry");
  }
  if (check && !contradicted) {  // the two-step estimate stands
    joint.jackknife.reason =
        "a check that agreed: the two-step estimate stands";
    if (agreeing_model) {
      *agreeing_model = AdjustedMetricModel(*run, input, joint.result);
    }
    return;
  }
  std::vector<int> image_order(input.problem.images.size());
  std::iota(image_order.begin(), image_order.end(), 0);
  std::sort(image_order.begin(), image_order.end(), [&](int a, int b) {
    return input.image_stamps_ns[a] < input.image_stamps_ns[b];
  });
  joint.jackknife = JackknifeJointExtrinsic(input.problem,
                                            options,
                                            image_order,
                                            inputs.joint_adjustment.jackknife,
                                            &joint.result);
  if (check) {
    // The contradiction was measured against the adjustment's covariance
    // before its jackknife. Where the jackknife widens it to cover the
    // difference, and the adjustment is then the less precise of the two in
    // every quantity that contradicted, it is the uncertain one (planar
    // robot poses on a banking road, half a drive left by a folded chunk:
    // metres off while the two-step was within its sigma), and the
    // two-step stands. Where the adjustment stays the more precise, a
    // difference its jackknife covers still says the two-step's sigma was
    // too small (the 300-image drive: the two-step's x 4.5 sigma off, the
    // adjustment's 3 times closer), and the adjustment is reported.
    joint.max_disagreement_sigmas_jackknifed = 0.0;
    bool adjustment_less_precise = true;
    for (const ExtrinsicDisagreement& d :
         ExtrinsicDisagreements(joint.result.odom_from_cam,
                                joint.result.covariance,
                                joint.two_step_odom_from_cam,
                                joint.two_step_covariance,
                                0.0)) {
      joint.max_disagreement_sigmas_jackknifed =
          std::max(joint.max_disagreement_sigmas_jackknifed, d.Sigmas());
      for (const ExtrinsicDisagreement& before : joint.disagreements) {
        if (before.quantity == d.quantity &&
            !(d.joint_stddev > d.two_step_stddev)) {
          adjustment_less_precise = false;
        }
      }
    }
    if (joint.max_disagreement_sigmas_jackknifed <= kJointContradictionSigmas &&
        adjustment_less_precise) {
      result.warnings.push_back(
          "joint adjustment check: the adjustment's own uncertainty, "
          "widened by its jackknife over stretches of the drive, covers "
          "the difference (" +
          FormatPrintf("%.1f", joint.max_disagreement_sigmas_jackknifed) +
          " sigma of it, " +
          FormatPrintf("%.1f", joint.max_disagreement_sigmas) +
          " before) and is wider than the two-step's: the two-step estimate "
          "stands");
      return;
    }
    result.warnings.push_back(
        "joint adjustment check: the images contradict the two-step "
        "estimate (" +
        FormatPrintf("%.1f", joint.max_disagreement_sigmas) +
        " sigma of their difference apart, more than " +
        FormatPrintf("%.0f", kJointContradictionSigmas) + "; " +
        FormatPrintf("%.1f", joint.max_disagreement_sigmas_jackknifed) +
        " after the adjustment's jackknife" +
        (joint.max_disagreement_sigmas_jackknifed <= kJointContradictionSigmas
             ? ", which leaves the adjustment the more precise"
             : "") +
        "): the joint adjustment's extrinsic and metric model are reported");
  }
  joint.adopted = true;
  // The repeatability test split the two-step's model, which the images
  // have just contradicted: its halves may disagree for that model's
  // failure, not for a mount that moved (road seed 9: a fold posed again
  // from the odometry at a chunk's start).
  for (std::string& warning : result.warnings) {
    if (check && warning.rfind("the calibration does not repeat:", 0) == 0) {
      warning +=
          "; the halves are the two-step's, whose model of the "
          "reconstruction the images contradict (joint adjustment): the "
          "disagreement may be that model's, not the mount's";
    }
  }
  AlignWithOdometry(*run, input, &joint.result);
  CompareScales(*run, input, &joint);
  AdoptJointExtrinsic(joint.result, &result);
  RefuseLooseAdoptedExtrinsic(inputs.calibration, &result);
  MetricSubModel adjusted = AdjustedMetricModel(*run, input, joint.result);
  run->metric_models.clear();
  run->metric_models.push_back(std::move(adjusted));
}

}  // namespace odomcal
