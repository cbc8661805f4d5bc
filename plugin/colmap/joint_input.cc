// The joint adjustment's problem from a project calibration
// (joint_input.h).
#include "odomcal/plugin/colmap/joint_input.h"

#include "odomcal/adapters/association.h"
#include "odomcal/adapters/odometry_increments.h"
#include "odomcal/adapters/odometry_interpolation_error.h"
#include "odomcal/plugin/colmap/odometry_inputs.h"
#include "odomcal/solver/hand_eye_residual.h"
#include "odomcal/solver/noise_estimation.h"
#include "odomcal/solver/planarity_check.h"

#include <algorithm>
#include <cmath>
#include <memory>
#include <set>
#include <utility>

namespace odomcal {
namespace {

std::optional<ProjectionModel> ProjectionOf(ColmapCameraModel model) {
  switch (model) {
    case ColmapCameraModel::kSimplePinhole:
      return ProjectionModel::kSimplePinhole;
    case ColmapCameraModel::kPinhole:
      return ProjectionModel::kPinhole;
    case ColmapCameraModel::kSimpleRadial:
      return ProjectionModel::kSimpleRadial;
    case ColmapCameraModel::kRadial:
      return ProjectionModel::kRadial;
    case ColmapCameraModel::kOpenCV:
      return ProjectionModel::kOpenCV;
    default:
      return std::nullopt;
  }
}

// The (x, y, yaw) part of a MotionCovariance ([rotation; translation]).
Eigen::Matrix3d PlanarCovariance(const MotionCovariance& covariance) {
  constexpr int kIndex[3] = {3, 4, 2};
  Eigen::Matrix3d planar;
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) {
      planar(r, c) = covariance(kIndex[r], kIndex[c]);
    }
  }
  return planar;
}

// The reconstruction's point that point `id` of `metric` (from input
// segment k) is, where known.
std::optional<ReconstructionPoint> ReconstructionPointOf(
    const ColmapCalibrationRun& run,
    const MetricSubModel& metric,
    int k,
    int64_t id) {
  if (metric.origin_from_sfm) {
    return ReconstructionPoint(run.segments.at(k).model_path, id);
  }
  const auto point = metric.reconstruction_points.find(id);
  if (point == metric.reconstruction_points.end()) return std::nullopt;
  return point->second;
}

}  // namespace

OdometryLink LinkOf(const MotionPair& pair,
                    int image_i,
                    int image_j,
                    const CalibrationResult& fit,
                    const NoiseModel& given) {
  MotionPair weighted = pair;
  NoiseModel noise = given;
  if (fit.noise_estimate) {
    weighted = ScaleCovariances({pair}, *fit.noise_estimate)[0];
    noise = fit.noise_estimate->noise;
  }
  OdometryLink link;
  link.image_i = image_i;
  link.image_j = image_j;
  link.odom_i_from_odom_j = PlanarFromRigid(pair.odom_i_from_odom_j);
  const StepSize step = MeasuredStep(weighted);
  link.covariance = PlanarCovariance(OdometryCovariance(weighted, noise, step));
  // The whole motion, for SE(3) robot poses. A noise model without a tilt
  // error of its own (a planar log's, or one the estimation left at 0)
  // gives the tilt the yaw's constant part: a 3-D log measures its tilt at
  // least as well as its heading.
  NoiseModel whole = noise;
  whole.odom_tilt_sigma_deg =
      std::max(whole.odom_tilt_sigma_deg, whole.odom_yaw_sigma_deg);
  link.motion_3d = OdometryMotion3d{pair.odom_i_from_odom_j,
                                    OdometryCovariance(weighted, whole, step)};
  return link;
}

std::optional<MotionPair> OdometryMotionBetween(const ColmapCalibrationRun& run,
                                                int64_t stamp_a_ns,
                                                int64_t stamp_b_ns) {
  const double gap_s = run.association.max_odometry_gap_s;
  const auto origin_from_odom_a =
      InterpolateOdometry(run.odometry, stamp_a_ns, gap_s, nullptr);
  const auto origin_from_odom_b =
      InterpolateOdometry(run.odometry, stamp_b_ns, gap_s, nullptr);
  if (!origin_from_odom_a || !origin_from_odom_b) return std::nullopt;
  MotionPair pair;
  pair.odom_i_from_odom_j = Inverse(*origin_from_odom_a) * *origin_from_odom_b;
  pair.stamp_i_ns = stamp_a_ns;
  pair.stamp_j_ns = stamp_b_ns;
  pair.odom_interpolation_covariance = RelativeMotionInterpolationCovariance(
      *origin_from_odom_a,
      OdometryInterpolationCovariance(run.odometry, stamp_a_ns),
      *origin_from_odom_b,
      OdometryInterpolationCovariance(run.odometry, stamp_b_ns));
  return pair;
}

namespace {

// Whether `camera` (of `metric`'s model) differs from the database's camera
// of its id: COLMAP's bundle adjustment refined it. False where that is not
// known: no database camera, or a model that numbers its cameras anew (the
// joint adjustment's, without origin_from_sfm).
bool ChangedByBundleAdjustment(
    const MetricSubModel& metric,
    const ColmapCamera& camera,
    const std::map<uint32_t, ColmapCamera>& database_cameras) {
  if (!metric.origin_from_sfm) return false;
  const auto given = database_cameras.find(camera.camera_id);
  if (given == database_cameras.end() || given->second.model != camera.model ||
      given->second.params.size() != camera.params.size()) {
    return false;
  }
  for (size_t k = 0; k < camera.params.size(); ++k) {
    const double before = given->second.params[k];
    if (std::abs(camera.params[k] - before) >
        1e-9 * std::max(1.0, std::abs(before))) {
      return true;
    }
  }
  return false;
}

}  // namespace

std::string AddMetricModels(
    const ColmapCalibrationRun& run,
    const std::map<std::string, int64_t>& stamp_of_image,
    JointIntrinsics intrinsics,
    JointInput* input) {
  JointAdjustmentProblem& problem = input->problem;
  const Rigid3d cam_from_odom = Inverse(run.check.result.odom_from_cam);
  std::map<std::string, int> image_index;
  std::map<std::pair<int, uint32_t>, int> camera_index;
  std::map<std::pair<int, int64_t>, int> point_index;
  std::set<std::pair<int, int>> observed;  // (joint image, input segment)
  for (const MetricSubModel& metric : run.metric_models) {
    const int k =
        run.check.input_segment_of_output_segment.at(metric.output_segment);
    for (const auto& [image_id, image] : metric.model.images) {
      const auto stamp = stamp_of_image.find(image.name);
      if (stamp == stamp_of_image.end()) continue;
      auto [where, inserted] = image_index.emplace(
          image.name, static_cast<int>(problem.images.size()));
      const int i = where->second;
      if (inserted) {
        const ColmapCamera& camera = metric.model.cameras.at(image.camera_id);
        const auto projection = ProjectionOf(camera.model);
        if (!projection) {
          return std::string("camera model ") +
                 ColmapCameraModelName(camera.model) +
                 " is not one it projects (SIMPLE_PINHOLE, PINHOLE, "
                 "SIMPLE_RADIAL, RADIAL, OPENCV)";
        }
        auto [camera_where, new_camera] =
            camera_index.emplace(std::make_pair(k, image.camera_id),
                                 static_cast<int>(problem.cameras.size()));
        if (new_camera) {
          JointCamera joint_camera{*projection, camera.params};
          joint_camera.held =
              intrinsics == JointIntrinsics::kAuto &&
              !ChangedByBundleAdjustment(metric, camera, run.database_cameras);
          problem.cameras.push_back(joint_camera);
          input->source_cameras.push_back(&camera);
        }
        JointImage joint_image;
        joint_image.camera = camera_where->second;
        joint_image.origin_from_odom =
            Inverse(image.cam_from_world) * cam_from_odom;
        problem.images.push_back(joint_image);
        input->image_names.push_back(image.name);
        input->image_stamps_ns.push_back(stamp->second +
                                         run.systematics.camera_time_offset_ns);
        input->source_images.push_back(&image);
      }
      // A part of a sub-model shares its points with the other parts: the
      // image's observations are added once per sub-model.
      if (!observed.insert({i, k}).second) continue;
      if (image.points2D.size() != input->source_images[i]->points2D.size()) {
        continue;  // another reconstruction with another keypoint list
      }
      for (size_t idx = 0; idx < image.points2D.size(); ++idx) {
        const ColmapPoint2D& point2D = image.points2D[idx];
        if (point2D.point3D_id == kColmapNoPoint3D) continue;
        const auto point = metric.model.points3D.find(point2D.point3D_id);
        if (point == metric.model.points3D.end()) continue;
        auto [point_where, new_point] =
            point_index.emplace(std::make_pair(k, point2D.point3D_id),
                                static_cast<int>(problem.points.size()));
        if (new_point) {
          problem.points.push_back(point->second.xyz);
          input->source_points.push_back(&point->second);
          input->reconstruction_points.push_back(
              ReconstructionPointOf(run, metric, k, point2D.point3D_id));
        }
        problem.observations.push_back({i, point_where->second, point2D.xy});
        input->observation_point2D.push_back(static_cast<uint32_t>(idx));
      }
    }
  }
  if (problem.images.empty()) return "the metric models hold no timed image";
  return "";
}

void AddOdometryLinks(const ColmapCalibrationInputs& inputs,
                      const ColmapCalibrationRun& run,
                      JointInput* input) {
  const CalibrationResult& fit = run.check.result;
  std::map<int64_t, int> image_at;
  for (size_t i = 0; i < input->image_stamps_ns.size(); ++i) {
    image_at.emplace(input->image_stamps_ns[i], static_cast<int>(i));
  }
  std::set<std::pair<int, int>> linked;
  const std::vector<char>& contradicts = run.check.contradicts_odometry;
  for (size_t p = 0; p < run.check.pairs.size(); ++p) {
    if (p < contradicts.size() && contradicts[p] != 0) continue;
    const MotionPair& pair = run.check.pairs[p];
    const auto i = image_at.find(pair.stamp_i_ns);
    const auto j = image_at.find(pair.stamp_j_ns);
    if (i == image_at.end() || j == image_at.end() || i->second == j->second)
      continue;
    if (!linked.insert({i->second, j->second}).second) continue;
    input->problem.links.push_back(
        LinkOf(pair, i->second, j->second, fit, inputs.calibration.noise));
    input->link_pairs.push_back(pair);
  }
  // Pieces: images joined by links or shared points, in time order.
  const int num_images = static_cast<int>(input->image_names.size());
  std::vector<int> piece(num_images);
  for (int i = 0; i < num_images; ++i) piece[i] = i;
  const auto find = [&piece](int i) {
    while (piece[i] != i) i = piece[i] = piece[piece[i]];
    return i;
  };
  for (const OdometryLink& link : input->problem.links) {
    piece[find(link.image_i)] = find(link.image_j);
  }
  std::vector<int> first_image_of_point(input->problem.points.size(), -1);
  for (const JointObservation& observation : input->problem.observations) {
    int& first = first_image_of_point[observation.point];
    if (first < 0) {
      first = observation.image;
    } else {
      piece[find(first)] = find(observation.image);
    }
  }
  std::vector<int> by_time(num_images);
  for (int i = 0; i < num_images; ++i) by_time[i] = i;
  std::sort(by_time.begin(), by_time.end(), [&](int a, int b) {
    return input->image_stamps_ns[a] < input->image_stamps_ns[b];
  });
  for (size_t n = 0; n + 1 < by_time.size(); ++n) {
    const int a = by_time[n];
    const int b = by_time[n + 1];
    if (find(a) == find(b)) continue;
    const std::optional<MotionPair> pair = OdometryMotionBetween(
        run, input->image_stamps_ns[a], input->image_stamps_ns[b]);
    if (!pair) continue;
    input->problem.links.push_back(
        LinkOf(*pair, a, b, fit, inputs.calibration.noise));
    input->link_pairs.push_back(*pair);
    ++input->num_joining_links;
    piece[find(a)] = find(b);
  }
  input->problem.motion_model = MotionModelOf(input->link_pairs);
}

RobotMotionModel MotionModelOf(const MotionPairs& links) {
  return IsPlanarOdometry(links) ? RobotMotionModel::kOnGround
                                 : RobotMotionModel::kSE3;
}

void AddOdometrySystematics(const ColmapCalibrationInputs& inputs,
                            const ColmapCalibrationRun& run,
                            bool refine_time_offset,
                            JointInput* input) {
  const SystematicsEstimate& estimate = run.systematics;
  const bool any = (refine_time_offset && estimate.time_offset_estimated) ||
                   estimate.intrinsics_estimated[0] ||
                   estimate.intrinsics_estimated[1] ||
                   estimate.intrinsics_estimated[2];
  if (!any || !run.odometry.planar) return;
  if (!input->logged_odometry) {
    input->logged_odometry =
        std::make_shared<const Trajectory>(ReadOdometryOf(inputs));
  }
  if (!input->logged_odometry->planar) return;
  MotionPairs pairs = input->link_pairs;
  AttachOdometrySamples(*input->logged_odometry, &pairs);
  for (size_t k = 0; k < pairs.size(); ++k) {
    if (!pairs[k].odometry_samples) return;
    input->problem.links[k].samples = pairs[k].odometry_samples;
  }
  JointSystematics systematics;
  systematics.intrinsics = estimate.intrinsics;
  systematics.refine_intrinsics = estimate.intrinsics_estimated;
  systematics.refine_time_offset =
      refine_time_offset && estimate.time_offset_estimated;
  input->problem.systematics = systematics;
}

}  // namespace odomcal
