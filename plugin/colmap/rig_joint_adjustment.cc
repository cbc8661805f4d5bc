#include "odomcal/plugin/colmap/rig_joint_adjustment.h"

#include "odomcal/plugin/colmap/joint_adjustment_stage.h"
#include "odomcal/plugin/colmap/joint_input.h"
#include "odomcal/solver/camera_pair.h"
#include "odomcal/solver/joint_adjustment_jackknife.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <numeric>
#include <optional>
#include <utility>

namespace odomcal {
namespace {

// Image name to time (camera clock) of one camera's calibrated segments.
std::map<std::string, int64_t> StampsOfImages(const ColmapCalibrationRun& run) {
  std::map<std::string, int64_t> stamps;
  for (const ColmapSegment& segment : run.segments) {
    for (size_t i = 0; i < segment.trajectory.poses.size(); ++i) {
      stamps.emplace(segment.image_names.at(i),
                     segment.trajectory.poses[i].stamp_ns);
    }
  }
  return stamps;
}

// The points of `all` by the reconstruction's point they are, and per
// point of `all` the number of observations of the camera whose estimate of
// it starts the adjustment.
struct SharedPoints {
  std::map<ReconstructionPoint, int> index;
  std::vector<int> observations;
};

// `part` appended to `all` as mount `mount`: its images, cameras, points
// and observations re-indexed (its links are not taken: see the header).
// A point `all` already holds from another camera of the same
// reconstruction stays one point, seen by both cameras' images.
void Append(const JointInput& part,
            int mount,
            SharedPoints* points,
            JointInput* all) {
  JointAdjustmentProblem& problem = all->problem;
  const int image_offset = static_cast<int>(problem.images.size());
  const int camera_offset = static_cast<int>(problem.cameras.size());
  for (JointImage image : part.problem.images) {
    image.camera += camera_offset;
    image.mount = mount;
    problem.images.push_back(image);
  }
  problem.cameras.insert(problem.cameras.end(),
                         part.problem.cameras.begin(),
                         part.problem.cameras.end());
  // A point shared with another camera starts at the estimate of the camera
  // that saw it in more images (one camera's estimate of a point it sees
  // nearly along its rays can lie far off).
  std::vector<int> observations(part.problem.points.size(), 0);
  for (const JointObservation& observation : part.problem.observations) {
    ++observations[observation.point];
  }
  std::vector<int> point_of(part.problem.points.size());
  for (size_t p = 0; p < part.problem.points.size(); ++p) {
    const int next = static_cast<int>(problem.points.size());
    const std::optional<ReconstructionPoint>& key =
        part.reconstruction_points.at(p);
    point_of[p] = key ? points->index.emplace(*key, next).first->second : next;
    if (point_of[p] == next) {
      problem.points.push_back(part.problem.points[p]);
      all->reconstruction_points.push_back(key);
      points->observations.push_back(observations[p]);
    } else if (observations[p] > points->observations[point_of[p]]) {
      problem.points[point_of[p]] = part.problem.points[p];
      points->observations[point_of[p]] = observations[p];
    }
  }
  for (JointObservation observation : part.problem.observations) {
    observation.image += image_offset;
    observation.point = point_of[observation.point];
    problem.observations.push_back(observation);
  }
  all->image_names.insert(
      all->image_names.end(), part.image_names.begin(), part.image_names.end());
  all->image_stamps_ns.insert(all->image_stamps_ns.end(),
                              part.image_stamps_ns.begin(),
                              part.image_stamps_ns.end());
}

// Points observed by images of two or more mounts.
int PointsAcrossMounts(const JointAdjustmentProblem& problem) {
  std::vector<int> first_mount(problem.points.size(), -1);
  std::vector<char> across(problem.points.size(), 0);
  for (const JointObservation& observation : problem.observations) {
    const int mount = problem.images[observation.image].mount;
    int& first = first_mount[observation.point];
    if (first < 0) {
      first = mount;
    } else if (first != mount) {
      across[observation.point] = 1;
    }
  }
  return static_cast<int>(std::count(across.begin(), across.end(), 1));
}

// One link per stretch between consecutive images in `order` (time order),
// each mount's image times moved by shift_ns[mount]; the links and
// link_pairs of `all` replaced. Returns the links between two mounts.
int ChainImagesInTime(const std::vector<int>& order,
                      const std::vector<int>& mount_of_image,
                      const std::vector<int64_t>& shift_ns,
                      const ColmapCalibrationRun& odometry_run,
                      const NoiseModel& noise,
                      JointInput* all) {
  all->problem.links.clear();
  all->link_pairs.clear();
  int across = 0;
  for (size_t n = 0; n + 1 < order.size(); ++n) {
    int a = order[n];
    int b = order[n + 1];
    int64_t stamp_a = all->image_stamps_ns[a] + shift_ns[mount_of_image[a]];
    int64_t stamp_b = all->image_stamps_ns[b] + shift_ns[mount_of_image[b]];
    if (stamp_b < stamp_a) {  // a shift moved b before a
      std::swap(a, b);
      std::swap(stamp_a, stamp_b);
    }
    const std::optional<MotionPair> pair =
        OdometryMotionBetween(odometry_run, stamp_a, stamp_b);
    if (!pair) continue;
    all->problem.links.push_back(
        LinkOf(*pair, a, b, odometry_run.check.result, noise));
    all->link_pairs.push_back(*pair);
    if (mount_of_image[a] != mount_of_image[b]) ++across;
  }
  return across;
}

// Each camera's clock offset is held at its own estimate in the
// adjustment; its uncertainty moves the robot's poses at that camera's
// images along the trajectory, and with them the extrinsics of every
// mount. Propagated to first order: per camera, the adjustment solved
// again (from its solution, at its noise levels) with that camera's images
// moved forward and back by a few of the offset's standard deviations; the
// change scaled to one standard deviation, its outer product added to the
// covariance (offsets independent between cameras). Returns how many it
// propagated.
int AddClockOffsetUncertainty(
    const std::vector<const ColmapCalibrationRun*>& runs,
    const ColmapCalibrationInputs& inputs,
    const std::vector<int>& order,
    const std::vector<int>& mount_of_image,
    const JointAdjustmentOptions& options,
    JointInput all,
    RigJointAdjustment* out) {
  JointAdjustmentResult& result = out->result;
  const int num_mounts = static_cast<int>(out->cameras.size());
  JointAdjustmentOptions resolve = options;
  resolve.pixel_sigma = result.pixel_sigma;
  resolve.estimate_odometry_noise = false;
  resolve.estimate_ground_tilt_rate = false;
  if (result.ground_tilt_rate_deg_per_m > 0.0) {
    resolve.ground_tilt_rate_deg_per_m = result.ground_tilt_rate_deg_per_m;
  }
  resolve.compute_covariance = false;
  resolve.max_reprojection_sigmas = std::numeric_limits<double>::max();
  resolve.progress = nullptr;
  // Started at the solution, without the observations it left out.
  JointAdjustmentProblem& problem = all.problem;
  for (size_t i = 0; i < problem.images.size(); ++i) {
    problem.images[i].origin_from_odom = result.origin_from_odom[i];
  }
  problem.points = result.points;
  problem.cameras = result.cameras;
  problem.odom_from_cam = result.odom_from_cam;
  problem.other_mounts = result.other_mounts;
  std::vector<JointObservation> kept;
  for (size_t k = 0; k < problem.observations.size(); ++k) {
    if (result.observation_error_px[k] >= 0.0) {
      kept.push_back(problem.observations[k]);
    }
  }
  problem.observations = std::move(kept);
  if (problem.systematics) {
    problem.systematics->intrinsics = result.intrinsics;
  }
  const ColmapCalibrationRun& first = *runs[out->cameras[0]];
  const double factor =
      result.odometry_sigma_ratio * result.odometry_sigma_ratio;
  const Eigen::Index size = Eigen::Index{5} * num_mounts;
  Eigen::MatrixXd added = Eigen::MatrixXd::Zero(size, size);
  int propagated = 0;
  for (int mount = 0; mount < num_mounts; ++mount) {
    const double stddev_s =
        runs[out->cameras[mount]]->systematics.camera_time_offset_stddev_s;
    if (!(stddev_s > 0.0)) continue;
    constexpr double kStepSigmas = 3.0;
    constexpr double kMinStepS = 5e-4;
    const double step_s = std::max(kStepSigmas * stddev_s, kMinStepS);
    // Central differences: the re-solves' own departure from the solution
    // (held noise levels, no outlier pass) cancels.
    std::vector<Eigen::VectorXd> moved_by;
    for (const double sign : {1.0, -1.0}) {
      std::vector<int64_t> shift_ns(num_mounts, 0);
      shift_ns[mount] = std::llround(sign * step_s * 1e9);
      ChainImagesInTime(order,
                        mount_of_image,
                        shift_ns,
                        first,
                        inputs.calibration.noise,
                        &all);
      for (OdometryLink& link : problem.links) link.covariance *= factor;
      // The moved links' logged odometry (a link without it fails the
      // re-solve, and the camera is not propagated).
      if (problem.systematics) {
        AddOdometrySystematics(
            inputs, first, /*refine_time_offset=*/false, &all);
      }
      const JointAdjustmentResult moved = AdjustJointly(problem, resolve);
      if (!moved.IsSuccess()) break;
      moved_by.push_back(MountDeviations(result, moved));
    }
    if (moved_by.size() != 2) continue;
    const Eigen::VectorXd change =
        (moved_by[0] - moved_by[1]) * (0.5 * stddev_s / step_s);
    added += change * change.transpose();
    ++propagated;
  }
  result.mounts_covariance += added;
  result.covariance = result.mounts_covariance.topLeftCorner<5, 5>();
  return propagated;
}

// Every mount's rotation (roll, pitch, yaw), x and y against its camera's
// own estimate; each quantity's difference over the sigma of the
// difference, the adjustment's covariance as it stands.
std::vector<RigDisagreement> MountsAgainstCameras(
    const std::vector<const ColmapCalibrationRun*>& runs,
    const RigJointAdjustment& joint) {
  std::vector<RigDisagreement> all;
  for (size_t mount = 0; mount < joint.cameras.size(); ++mount) {
    const CalibrationResult& own = runs[joint.cameras[mount]]->check.result;
    const int m = static_cast<int>(mount);
    for (const ExtrinsicDisagreement& d :
         ExtrinsicDisagreements(joint.result.MountOdomFromCam(m),
                                joint.result.MountCovariance(m),
                                own.odom_from_cam,
                                own.covariance->topLeftCorner<5, 5>(),
                                0.0)) {
      all.push_back({joint.cameras[mount], d});
    }
  }
  return all;
}

double MaxSigmas(const std::vector<RigDisagreement>& all) {
  double max = 0.0;
  for (const RigDisagreement& d : all) max = std::max(max, d.quantity.Sigmas());
  return max;
}

// The check's verdict once the adjustment has its jackknife: whether the
// cameras' own estimates stand (the widened adjustment covers every
// difference and is the less precise in each quantity that contradicted).
bool OwnEstimatesStand(const std::vector<const ColmapCalibrationRun*>& runs,
                       RigJointAdjustment* joint) {
  const std::vector<RigDisagreement> after = MountsAgainstCameras(runs, *joint);
  joint->max_disagreement_sigmas_jackknifed = MaxSigmas(after);
  if (joint->max_disagreement_sigmas_jackknifed > kJointContradictionSigmas) {
    return false;
  }
  for (const RigDisagreement& d : after) {
    for (const RigDisagreement& before : joint->disagreements) {
      if (before.camera == d.camera &&
          before.quantity.quantity == d.quantity.quantity &&
          !(d.quantity.joint_stddev > d.quantity.two_step_stddev)) {
        return false;
      }
    }
  }
  return true;
}

}  // namespace

int RigJointAdjustment::MountOf(int camera) const {
  const auto it = std::find(cameras.begin(), cameras.end(), camera);
  return it == cameras.end() ? -1 : static_cast<int>(it - cameras.begin());
}

RigJointAdjustment AdjustRigJointly(
    const std::vector<const ColmapCalibrationRun*>& runs,
    const std::vector<std::string>& names,
    const ColmapCalibrationInputs& inputs,
    const CalibrationProgress& progress) {
  RigJointAdjustment out;
  out.use = inputs.joint_adjustment.use;
  if (out.use == JointAdjustmentUse::kOff) return out;
  JointInput all;
  SharedPoints points;
  std::vector<int> mount_of_image;
  std::string left_out;
  for (size_t k = 0; k < runs.size(); ++k) {
    const ColmapCalibrationRun* run = runs[k];
    if (run == nullptr || !ExtrinsicOf(run->check.result) ||
        run->metric_models.empty()) {
      continue;
    }
    if (run->check.result.observability.translation_z_source ==
        TranslationZSource::kMotion) {
      // As one camera's adjustment: it holds the extrinsic's z, which the
      // tilts determined with an uncertainty the adjustment would drop.
      left_out += (left_out.empty() ? "" : "; ") + names.at(k) +
                  ": it holds the extrinsic's z, which the SE(3) odometry's "
                  "tilts determine here";
      continue;
    }
    JointInput part;
    part.problem.odom_from_cam = run->check.result.odom_from_cam;
    if (const std::string why =
            AddMetricModels(*run,
                            StampsOfImages(*run),
                            inputs.joint_adjustment.intrinsics,
                            &part);
        !why.empty()) {
      left_out += (left_out.empty() ? "" : "; ") + names.at(k) + ": " + why;
      continue;
    }
    const int mount = static_cast<int>(out.cameras.size());
    if (mount == 0) {
      all.problem.odom_from_cam = part.problem.odom_from_cam;
    } else {
      all.problem.other_mounts.push_back(part.problem.odom_from_cam);
    }
    out.cameras.push_back(static_cast<int>(k));
    Append(part, mount, &points, &all);
    mount_of_image.resize(all.problem.images.size(), mount);
    out.mount_of_camera.resize(all.problem.cameras.size(), mount);
  }
  if (out.cameras.size() < 2) {
    out.skipped = "fewer than two cameras calibrated with metric models" +
                  (left_out.empty() ? std::string() : " (" + left_out + ")");
    return out;
  }
  // One chain of links through every image in time order, from the first
  // camera's odometry and noise model (the odometry is one; each camera's
  // run holds it at that camera's clock offset, already in the stamps).
  const ColmapCalibrationRun& first = *runs[out.cameras[0]];
  std::vector<int> order(all.problem.images.size());
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(), [&](int a, int b) {
    return all.image_stamps_ns[a] < all.image_stamps_ns[b];
  });
  out.num_links_across_cameras =
      ChainImagesInTime(order,
                        mount_of_image,
                        std::vector<int64_t>(out.cameras.size(), 0),
                        first,
                        inputs.calibration.noise,
                        &all);
  // The odometry's intrinsics refined as one camera's adjustment refines
  // them, from the first camera's estimate; each camera's clock offset
  // stays its own estimate (one change common to all would not fit them),
  // its uncertainty propagated below.
  all.problem.motion_model = MotionModelOf(all.link_pairs);
  AddOdometrySystematics(inputs, first, /*refine_time_offset=*/false, &all);
  out.num_images = static_cast<int>(all.problem.images.size());
  out.num_points = static_cast<int>(all.problem.points.size());
  out.num_points_across_cameras = PointsAcrossMounts(all.problem);
  out.num_links = static_cast<int>(all.problem.links.size());

  const JointAdjustmentOptions options = JointOptionsWithProgress(
      inputs.joint_adjustment, progress, "rig joint adjustment");
  out.ran = true;
  out.cameras_before = all.problem.cameras;
  out.refine_intrinsics = options.refine_intrinsics;
  out.result = AdjustJointly(all.problem, options);
  if (!out.result.IsSuccess()) return out;
  const bool check = out.use == JointAdjustmentUse::kCheck;
  if (check) {
    const std::vector<RigDisagreement> before = MountsAgainstCameras(runs, out);
    out.max_disagreement_sigmas = MaxSigmas(before);
    for (const RigDisagreement& d : before) {
      if (d.quantity.Sigmas() > kJointContradictionSigmas) {
        out.disagreements.push_back(d);
      }
    }
    if (out.disagreements.empty()) {
      out.jackknife.reason =
          "a check that agreed: each camera's own estimate stands";
      return out;
    }
  }
  out.jackknife = JackknifeJointExtrinsic(all.problem,
                                          options,
                                          order,
                                          inputs.joint_adjustment.jackknife,
                                          &out.result);
  out.num_clock_offsets_propagated = AddClockOffsetUncertainty(
      runs, inputs, order, mount_of_image, options, std::move(all), &out);
  out.adopted = !check || !OwnEstimatesStand(runs, &out);
  return out;
}

}  // namespace odomcal
