// How the joint adjustment's robot poses (RobotMotionModel) fare on ground
// that pitches and banks: per seed, the simulated drive of
// datasets/simulation/joint_scene.h (80 images, 0.5 px, 5 % scale drift)
// on ground sloped by up to --slope_deg (waves whose phases vary with the
// seed), adjusted with level poses and a planar log (kPlanar), whole poses
// and a planar log (kOnGround) and whole poses and a 3-D log (kSE3); each
// with its jackknife over 8 stretches. Prints, per run, the pixel sigma,
// the estimated tilt rate, the stated roll and pitch sigma, and roll /
// pitch / yaw / x / y error over the stated sigma; then per model the share
// within 3 sigma and the RMS.
//
//   <build>/benchmarks/ground_poses_study [--slope_deg 3] [--seeds 10]
#include "odomcal/datasets/simulation/joint_scene.h"
#include "odomcal/solver/angles.h"
#include "odomcal/solver/joint_adjustment.h"
#include "odomcal/solver/joint_adjustment_jackknife.h"

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <numeric>
#include <vector>

namespace odomcal {
namespace {

struct Tally {
  int runs = 0, within = 0, values = 0;
  double sum_squares = 0.0;
};

int Main(int argc, char** argv) {
  double slope_deg = 3.0;
  int num_seeds = 10;
  for (int k = 1; k + 1 < argc; k += 2) {
    if (std::strcmp(argv[k], "--slope_deg") == 0) {
      slope_deg = std::atof(argv[k + 1]);
    } else if (std::strcmp(argv[k], "--seeds") == 0) {
      num_seeds = std::atoi(argv[k + 1]);
    } else {
      std::fprintf(stderr, "unknown flag %s\n", argv[k]);
      return 2;
    }
  }
  const RobotMotionModel models[] = {RobotMotionModel::kPlanar,
                                     RobotMotionModel::kOnGround,
                                     RobotMotionModel::kSE3};
  Tally tallies[3];
  std::printf(
      "slope %.1f deg: model seed | pixel sigma | tilt rate deg/m | "
      "roll / pitch sigma deg | error / sigma (roll pitch yaw x y)\n",
      slope_deg);
  for (int seed = 1; seed <= num_seeds; ++seed) {
    for (int m = 0; m < 3; ++m) {
      JointSceneOptions options;
      options.seed = static_cast<unsigned>(seed);
      options.pixel_sigma = 0.5;
      options.drift = 0.05;
      options.ground_slope_deg = slope_deg;
      options.se3_odometry = models[m] == RobotMotionModel::kSE3;
      JointScene scene = SimulateJointScene(options);
      scene.problem.motion_model = models[m];
      JointAdjustmentResult result =
          AdjustJointly(scene.problem, JointAdjustmentOptions());
      if (!result.IsSuccess()) {
        std::printf("%s %d | %s: %s\n",
                    ToString(models[m]),
                    seed,
                    ToString(result.status),
                    result.message.c_str());
        continue;
      }
      std::vector<int> order(scene.problem.images.size());
      std::iota(order.begin(), order.end(), 0);
      JackknifeJointExtrinsic(scene.problem,
                              JointAdjustmentOptions(),
                              order,
                              JointJackknifeOptions(),
                              &result);
      Eigen::Matrix<double, 5, 1> error;
      error.head<3>() = LogRotation(result.odom_from_cam.rotation *
                                    scene.odom_from_cam.rotation.conjugate());
      error.tail<2>() =
          (result.odom_from_cam.translation - scene.odom_from_cam.translation)
              .head<2>();
      std::printf("%s %d | %.2f | %.3f | %.4f / %.4f |",
                  ToString(models[m]),
                  seed,
                  result.pixel_sigma,
                  result.ground_tilt_rate_deg_per_m,
                  std::sqrt(result.covariance(0, 0)) / kDegToRad,
                  std::sqrt(result.covariance(1, 1)) / kDegToRad);
      Tally& tally = tallies[m];
      ++tally.runs;
      for (int k = 0; k < 5; ++k) {
        const double ratio = error[k] / std::sqrt(result.covariance(k, k));
        std::printf(" %+.1f", ratio);
        tally.within += std::abs(ratio) <= 3.0 ? 1 : 0;
        tally.sum_squares += ratio * ratio;
        ++tally.values;
      }
      std::printf("\n");
    }
  }
  for (int m = 0; m < 3; ++m) {
    const Tally& t = tallies[m];
    if (t.values == 0) continue;
    std::printf(
        "%s: %d runs, %d of %d parameters within 3 sigma, RMS "
        "error/sigma %.2f\n",
        ToString(models[m]),
        t.runs,
        t.within,
        t.values,
        std::sqrt(t.sum_squares / t.values));
  }
  return 0;
}

}  // namespace
}  // namespace odomcal

int main(int argc, char** argv) { return odomcal::Main(argc, argv); }
