// Time and peak memory of the joint adjustment (solver/joint_adjustment.h)
// and its jackknife against the drive's length, on the simulated drives of
// datasets/simulation/joint_scene.h (30 points per image, 0.5 px noise, 5 %
// scale drift to take out). One adjustment per size; the counters give the
// problem's size and the process's peak resident memory so far (sizes run
// in increasing order, so each row's peak is its own).
//
//   cmake --build <build> --target joint_adjustment_benchmark
//   <build>/benchmarks/joint_adjustment_benchmark
#include "odomcal/datasets/simulation/joint_scene.h"
#include "odomcal/solver/joint_adjustment.h"
#include "odomcal/solver/joint_adjustment_jackknife.h"

#include <sys/resource.h>

#include <benchmark/benchmark.h>

#include <numeric>
#include <thread>
#include <vector>

namespace odomcal {
namespace {

double PeakResidentMiB() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return static_cast<double>(usage.ru_maxrss) / 1024.0;  // KiB on Linux
}

JointAdjustmentOptions Options() {
  JointAdjustmentOptions options;
  options.num_threads =
      std::max(1, static_cast<int>(std::thread::hardware_concurrency()));
  return options;
}

JointScene Scene(benchmark::State& state) {
  JointSceneOptions scene;
  scene.num_images = static_cast<int>(state.range(0));
  scene.points_per_image = 30;
  return SimulateJointScene(scene);
}

void BM_AdjustJointly(benchmark::State& state) {
  const JointScene scene = Scene(state);
  const JointAdjustmentOptions options = Options();
  for (auto _ : state) {
    const JointAdjustmentResult result = AdjustJointly(scene.problem, options);
    if (!result.IsSuccess()) state.SkipWithError(result.message.c_str());
    benchmark::DoNotOptimize(result.covariance);
    state.counters["solve_s"] = result.solve_time_s;
    state.counters["covariance_s"] = result.covariance_time_s;
    state.counters["iterations"] = result.num_iterations;
  }
  state.counters["observations"] =
      static_cast<double>(scene.problem.observations.size());
  state.counters["points"] = static_cast<double>(scene.problem.points.size());
  state.counters["peak_MiB"] = PeakResidentMiB();
}

void BM_JackknifeJointExtrinsic(benchmark::State& state) {
  const JointScene scene = Scene(state);
  const JointAdjustmentOptions options = Options();
  const JointAdjustmentResult full = AdjustJointly(scene.problem, options);
  if (!full.IsSuccess()) {
    state.SkipWithError(full.message.c_str());
    return;
  }
  std::vector<int> order(scene.problem.images.size());
  std::iota(order.begin(), order.end(), 0);
  for (auto _ : state) {
    JointAdjustmentResult result = full;
    const JointJackknife jackknife = JackknifeJointExtrinsic(
        scene.problem, options, order, JointJackknifeOptions(), &result);
    if (!jackknife.ran) state.SkipWithError(jackknife.reason.c_str());
    benchmark::DoNotOptimize(result.covariance);
  }
  state.counters["peak_MiB"] = PeakResidentMiB();
}

BENCHMARK(BM_AdjustJointly)
    ->Arg(100)
    ->Arg(300)
    ->Arg(1000)
    ->Iterations(1)
    ->Unit(benchmark::kSecond);
BENCHMARK(BM_JackknifeJointExtrinsic)
    ->Arg(100)
    ->Arg(300)
    ->Arg(1000)
    ->Iterations(1)
    ->Unit(benchmark::kSecond);

}  // namespace
}  // namespace odomcal
