// Throughput of `odomcal simulate`: Monte Carlo trials per second of the
// paper's evaluation (datasets/paper/paper_evaluation.h) at the nominal sweep
// point (datasets/paper/paper_sweeps.h: 20 motions, odometry yaw SD 0.05 rad,
// translation SD 5 %, 1 px), for both camera-noise modes. One trial =
// simulate (landmarks: 20 two-view multi-start bundle adjustments) + ALS,
// ALSP-L, ALSP-orth, CM (200 RANSAC samples) + 4 batch refinements (2-6
// refinements each with the default inlier rounds). items_per_second counts
// trials. BM_Trial runs on the calling thread; BM_SweepPoint runs 20 trials per
// iteration on `threads` std::threads.
//   simulate_benchmark --benchmark_min_time=2

#include "odomcal/datasets/paper/paper_evaluation.h"
#include "odomcal/datasets/paper/paper_simulation.h"
#include "odomcal/datasets/paper/paper_sweeps.h"

#include <benchmark/benchmark.h>

#include <cstdint>

namespace odomcal {
namespace {

constexpr uint64_t kSeed = 20120514;

CameraNoiseMode Mode(const benchmark::State& state) {
  return state.range(0) == 0 ? CameraNoiseMode::kParametric
                             : CameraNoiseMode::kLandmarks;
}

void BM_Trial(benchmark::State& state) {
  const PaperSimulationOptions simulation = NominalPaperSimulation(Mode(state));
  const EvaluationOptions options;
  int trial = 0;
  for (auto _ : state) {
    const uint64_t seed = TrialSeed(kSeed, "benchmark", 0, trial++);
    std::mt19937_64 rng(seed);
    const PaperSimulation data = SimulatePaperMotions(simulation, &rng);
    benchmark::DoNotOptimize(EvaluateTrial(data, options, seed));
  }
  state.SetItemsProcessed(state.iterations());
  state.SetLabel(ToString(Mode(state)));
}
BENCHMARK(BM_Trial)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond);

void BM_SweepPoint(benchmark::State& state) {
  const PaperSimulationOptions simulation = NominalPaperSimulation(Mode(state));
  const int threads = static_cast<int>(state.range(1));
  constexpr int kTrials = 20;
  int point = 0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(RunSweepPoint(simulation,
                                           EvaluationOptions(),
                                           "benchmark",
                                           point++,
                                           0.0,
                                           kTrials,
                                           threads,
                                           kSeed));
  }
  state.SetItemsProcessed(state.iterations() * kTrials);
  state.SetLabel(ToString(Mode(state)) + ", " + std::to_string(threads) +
                 " threads");
}
BENCHMARK(BM_SweepPoint)
    ->Args({0, 1})
    ->Args({0, 2})
    ->Args({1, 1})
    ->Args({1, 2})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

}  // namespace
}  // namespace odomcal
