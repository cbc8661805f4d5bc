#include "odomcal/solver/stretch_consistency.h"

#include "odomcal/solver/calibrate.h"
#include "odomcal/solver/hand_eye_ransac.h"
#include "odomcal/solver/noise_estimation.h"

#include <Eigen/QR>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <set>

namespace odomcal {
namespace {

// Per-pair scales under the noise the fit's covariance uses: the noise it
// estimated from the data when it did (the options' model and the pairs' own
// covariances scaled by the variance factors), else the given noise.
std::vector<PairMetricScale> PerPairMetricScalesOfFit(
    const MotionPairs& pairs,
    const CalibrationResult& fit,
    const CalibrationOptions& options) {
  if (!fit.noise_estimate) {
    return PerPairMetricScales(
        pairs, fit.odom_from_cam, fit.metric_scales, options.noise);
  }
  return PerPairMetricScales(ScaleCovariances(pairs, *fit.noise_estimate),
                             fit.odom_from_cam,
                             fit.metric_scales,
                             fit.noise_estimate->noise);
}

// Per pair: ContradictsOdometry under `fit`.
std::vector<char> ContradictingPairs(const MotionPairs& pairs,
                                     const CalibrationResult& fit,
                                     const CalibrationOptions& options) {
  const std::vector<char>& used = fit.diagnostics.inlier_mask;
  std::vector<char> contradicts(pairs.size(), 0);
  for (size_t i = 0; i < pairs.size(); ++i) {
    contradicts[i] = ContradictsOdometry(
        pairs[i], i < used.size() && used[i] != 0, fit, options);
  }
  return contradicts;
}

// Runs of consecutive pairs (by time) the fit did not use, within each input
// segment, that hold at least `min_run_pairs` pairs which contradict the
// odometry. The run takes in the unused pairs around and between those: a
// fold's edges degrade gradually (on the long drive, 0.05-0.5 deg and
// 2-14 mm before the degrees-off pairs), and one pair in the middle that
// happens to pass the gate does not split a fold in two.
std::vector<InconsistentStretch> FindContradictingRuns(
    const MotionPairs& pairs,
    const std::vector<char>& used,
    const std::vector<char>& contradicts,
    int min_run_pairs) {
  std::map<int, std::vector<int>> by_segment;
  for (size_t i = 0; i < pairs.size(); ++i) {
    by_segment[pairs[i].segment].push_back(static_cast<int>(i));
  }
  const auto is_used = [&](int i) {
    return static_cast<size_t>(i) < used.size() && used[i] != 0;
  };
  std::vector<InconsistentStretch> runs;
  for (auto& [segment, members] : by_segment) {
    std::stable_sort(members.begin(), members.end(), [&](int a, int b) {
      return pairs[a].stamp_i_ns < pairs[b].stamp_i_ns;
    });
    size_t k = 0;
    while (k < members.size()) {
      if (is_used(members[k])) {
        ++k;
        continue;
      }
      size_t end = k;
      int num_contradicting = 0;
      while (end < members.size() && !is_used(members[end])) {
        num_contradicting += contradicts[members[end]] != 0;
        ++end;
      }
      if (num_contradicting >= min_run_pairs) {
        InconsistentStretch run;
        run.input_segment = segment;
        run.first_pair = members[k];
        run.last_pair = members[end - 1];
        run.first_stamp_ns = pairs[members[k]].stamp_i_ns;
        run.last_stamp_ns = pairs[members[end - 1]].stamp_j_ns;
        run.num_pairs = static_cast<int>(end - k);
        runs.push_back(run);
      }
      k = end;
    }
  }
  return runs;
}

// True when the run's pairs fit `odom_from_cam` with a scale of their own.
bool RunIsSelfConsistent(const MotionPairs& pairs,
                         const InconsistentStretch& run,
                         const Rigid3d& odom_from_cam,
                         const CalibrationOptions& options,
                         double min_inlier_ratio) {
  MotionPairs members;
  for (const MotionPair& pair : pairs) {
    if (pair.segment == run.input_segment &&
        pair.stamp_i_ns >= run.first_stamp_ns &&
        pair.stamp_j_ns <= run.last_stamp_ns) {
      members.push_back(pair);
      members.back().segment = 0;
    }
  }
  std::vector<int> all(members.size());
  for (size_t i = 0; i < all.size(); ++i) all[i] = static_cast<int>(i);
  std::vector<double> scales;
  CompleteMetricScales(members, all, 1, odom_from_cam, &scales);
  if (!(scales[0] > 0.0)) return false;
  std::vector<int> inliers;
  RansacScore(members, all, odom_from_cam, scales, options, &inliers);
  return inliers.size() >= min_inlier_ratio * members.size();
}

// Output segments with fewer than `min_pairs` pairs (e.g. a short tail after
// a cut) cannot determine their own scale: their pairs are dropped and the
// remaining segments renumbered densely.
void DropShortSegments(int min_pairs, StretchCheckResult* check) {
  std::map<int, int> count;
  for (const MotionPair& pair : check->pairs) ++count[pair.segment];
  std::map<int, int> renumbered;
  std::vector<int> input_segment_of_output;
  for (const auto& [segment, num_pairs] : count) {
    if (num_pairs >= min_pairs) {
      renumbered[segment] = static_cast<int>(renumbered.size());
      input_segment_of_output.push_back(
          check->input_segment_of_output_segment[segment]);
    }
  }
  MotionPairs kept;
  std::vector<int> kept_input;
  for (size_t i = 0; i < check->pairs.size(); ++i) {
    const auto it = renumbered.find(check->pairs[i].segment);
    if (it == renumbered.end()) continue;
    kept.push_back(check->pairs[i]);
    kept.back().segment = it->second;
    kept_input.push_back(check->input_pair_of_output[i]);
  }
  for (InconsistentStretch& run : check->stretches) {
    if (!run.kept_as_segment) continue;
    const auto it = renumbered.find(run.output_segment);
    if (it == renumbered.end()) {
      run.kept_as_segment = false;
      run.output_segment = -1;
    } else {
      run.output_segment = it->second;
    }
  }
  check->pairs = std::move(kept);
  check->input_pair_of_output = std::move(kept_input);
  check->input_segment_of_output_segment = std::move(input_segment_of_output);
}

// Relabels the pairs: within an input segment a new output segment starts at
// each run of `check->stretches` and after it; dropped runs lose their pairs.
// Then calibrates again.
void CutOutlierRuns(const MotionPairs& pairs,
                    const CalibrationOptions& options,
                    const StretchOptions& stretch_options,
                    StretchCheckResult* check) {
  // Runs are found with RANSAC's gate, but whether one is a part at another
  // scale is judged under the noise the fit estimated from the data, when it
  // did (stricter): a run kept as a segment re-enters the fit, so it must
  // fit its own scale as well as the rest fit theirs. A run in doubt is
  // dropped: less coverage, not a bent extrinsic.
  const MotionPairs* judged_pairs = &pairs;
  CalibrationOptions judged_options = options;
  MotionPairs weighted_pairs;
  if (check->result.noise_estimate) {
    weighted_pairs = ScaleCovariances(pairs, *check->result.noise_estimate);
    judged_pairs = &weighted_pairs;
    judged_options.noise = check->result.noise_estimate->noise;
  }
  std::vector<int> run_of_pair(pairs.size(), -1);
  for (size_t r = 0; r < check->stretches.size(); ++r) {
    InconsistentStretch& run = check->stretches[r];
    run.kept_as_segment = RunIsSelfConsistent(*judged_pairs,
                                              run,
                                              check->result.odom_from_cam,
                                              judged_options,
                                              stretch_options.min_inlier_ratio);
    for (size_t i = 0; i < pairs.size(); ++i) {
      if (pairs[i].segment == run.input_segment &&
          pairs[i].stamp_i_ns >= run.first_stamp_ns &&
          pairs[i].stamp_j_ns <= run.last_stamp_ns) {
        run_of_pair[i] = static_cast<int>(r);
      }
    }
  }
  std::vector<int> order(pairs.size());
  for (size_t i = 0; i < order.size(); ++i) order[i] = static_cast<int>(i);
  std::stable_sort(order.begin(), order.end(), [&](int a, int b) {
    if (pairs[a].segment != pairs[b].segment) {
      return pairs[a].segment < pairs[b].segment;
    }
    return pairs[a].stamp_i_ns < pairs[b].stamp_i_ns;
  });
  check->pairs.clear();
  check->input_pair_of_output.clear();
  check->input_segment_of_output_segment.clear();
  int current_input_segment = -1;
  int current_run = std::numeric_limits<int>::min();
  int output_segment = -1;
  for (const int i : order) {
    const int run = run_of_pair[i];
    if (pairs[i].segment != current_input_segment || run != current_run) {
      current_input_segment = pairs[i].segment;
      current_run = run;
      const bool dropped = run >= 0 && !check->stretches[run].kept_as_segment;
      if (!dropped) {
        ++output_segment;
        check->input_segment_of_output_segment.push_back(pairs[i].segment);
        if (run >= 0) check->stretches[run].output_segment = output_segment;
      }
    }
    if (run >= 0 && !check->stretches[run].kept_as_segment) continue;
    MotionPair relabelled = pairs[i];
    relabelled.segment = output_segment;
    check->pairs.push_back(relabelled);
    check->input_pair_of_output.push_back(i);
  }
  DropShortSegments(stretch_options.min_run_pairs, check);
  check->split = true;
  check->result = CalibrateOdomCam(check->pairs, options);
}

// Cuts output segments where the step-length check finds a change of scale
// (among the inliers of the current fit) and calibrates again.
void CutScaleChanges(const CalibrationOptions& options,
                     const ScaleChangeOptions& scale_options,
                     StretchCheckResult* check) {
  const CalibrationResult& fit = check->result;
  MotionPairs inliers;
  for (size_t i = 0; i < check->pairs.size(); ++i) {
    if (fit.diagnostics.inlier_mask.at(i)) inliers.push_back(check->pairs[i]);
  }
  const std::vector<ScaleChange> changes = FindScaleChanges(
      inliers, PerPairMetricScalesOfFit(inliers, fit, options), scale_options);
  if (changes.empty()) return;

  // Output segment k becomes parts (k, 0), (k, 1), ... numbered densely.
  std::map<std::pair<int, int>, int> part_segment;
  std::vector<std::pair<int, int>> part_of_pair(check->pairs.size());
  for (size_t i = 0; i < check->pairs.size(); ++i) {
    const MotionPair& pair = check->pairs[i];
    int part = 0;
    for (const ScaleChange& change : changes) {
      if (change.segment == pair.segment && pair.stamp_i_ns >= change.stamp_ns)
        ++part;
    }
    part_of_pair[i] = {pair.segment, part};
    part_segment[part_of_pair[i]] = 0;
  }
  std::vector<int> input_segment_of_output;
  for (auto& [part, segment] : part_segment) {
    segment = static_cast<int>(input_segment_of_output.size());
    input_segment_of_output.push_back(
        check->input_segment_of_output_segment.at(part.first));
  }
  for (const ScaleChange& change : changes) {
    ScaleChangeCut cut;
    cut.input_segment =
        check->input_segment_of_output_segment.at(change.segment);
    cut.stamp_ns = change.stamp_ns;
    cut.scale_before = change.scale_before;
    cut.scale_after = change.scale_after;
    cut.f_statistic = change.f_statistic;
    cut.f_threshold = change.f_threshold;
    check->scale_changes.push_back(cut);
  }
  for (InconsistentStretch& run : check->stretches) {
    if (!run.kept_as_segment) continue;
    int part = 0;
    for (const ScaleChange& change : changes) {
      if (change.segment == run.output_segment &&
          run.first_stamp_ns >= change.stamp_ns)
        ++part;
    }
    run.output_segment = part_segment.at({run.output_segment, part});
  }
  for (size_t i = 0; i < check->pairs.size(); ++i) {
    check->pairs[i].segment = part_segment.at(part_of_pair[i]);
  }
  check->input_segment_of_output_segment = std::move(input_segment_of_output);
  check->split = true;
  check->result = CalibrateOdomCam(check->pairs, options);
}

// Weighted least squares of  a_i = s0 + slope (t_i - t_first) + g_i . theta
// over the per-pair scales a_i of one input segment's used pairs (t_i: the
// pair's mid time, g_i: its lever arm gradient): the drift is
// slope * duration / s0, its variance scaled by the fit's own scatter when
// that exceeds the noise model.
void MeasureDrift(const std::vector<PairMetricScale>& scales,
                  const std::vector<double>& times_s,
                  double duration_s,
                  ScaleDrift* drift) {
  Eigen::Matrix4d normal = Eigen::Matrix4d::Zero();
  Eigen::Vector4d rhs = Eigen::Vector4d::Zero();
  double waa = 0.0;
  int n = 0;
  for (size_t i = 0; i < scales.size(); ++i) {
    const PairMetricScale& value = scales[i];
    if (!std::isfinite(value.scale) || !std::isfinite(value.stddev) ||
        !(value.stddev > 0.0)) {
      continue;
    }
    const double w = 1.0 / (value.stddev * value.stddev);
    Eigen::Vector4d row;
    row << 1.0, times_s[i], value.scale_per_lever_arm_xy;
    normal += w * row * row.transpose();
    rhs += w * value.scale * row;
    waa += w * value.scale * value.scale;
    ++n;
  }
  if (n < 5) return;
  const Eigen::Matrix4d covariance =
      Eigen::CompleteOrthogonalDecomposition<Eigen::Matrix4d>(normal)
          .pseudoInverse();
  const Eigen::Vector4d solution = covariance * rhs;
  const double chi_square = std::max(0.0, waa - solution.dot(rhs));
  const double variance_factor = std::max(1.0, chi_square / (n - 4));
  const double s0 = solution(0);
  if (!(std::abs(s0) > 0.0)) return;
  drift->relative_drift = solution(1) * duration_s / s0;
  drift->relative_drift_stddev =
      std::sqrt(variance_factor * std::max(0.0, covariance(1, 1))) *
      duration_s / std::abs(s0);
  drift->trend_measured = true;
}

// One ScaleDrift per input segment with a scale cut, from the final fit.
void MeasureScaleDrifts(const CalibrationOptions& options,
                        StretchCheckResult* check) {
  const CalibrationResult& fit = check->result;
  if (!fit.has_estimate) return;
  std::set<int> cut_inputs;
  for (const ScaleChangeCut& cut : check->scale_changes) {
    cut_inputs.insert(cut.input_segment);
  }
  const std::vector<PairMetricScale> scales =
      PerPairMetricScalesOfFit(check->pairs, fit, options);
  for (const int input : cut_inputs) {
    ScaleDrift drift;
    drift.input_segment = input;
    drift.first_stamp_ns = std::numeric_limits<int64_t>::max();
    drift.last_stamp_ns = std::numeric_limits<int64_t>::min();
    std::map<int, ScaleStretch> stretches;
    std::vector<int> members;
    for (size_t i = 0; i < check->pairs.size(); ++i) {
      const MotionPair& pair = check->pairs[i];
      if (check->input_segment_of_output_segment.at(pair.segment) != input)
        continue;
      auto [it, inserted] = stretches.try_emplace(pair.segment);
      ScaleStretch& stretch = it->second;
      if (inserted) {
        stretch.output_segment = pair.segment;
        stretch.first_stamp_ns = pair.stamp_i_ns;
        stretch.last_stamp_ns = pair.stamp_j_ns;
      }
      stretch.first_stamp_ns =
          std::min(stretch.first_stamp_ns, pair.stamp_i_ns);
      stretch.last_stamp_ns = std::max(stretch.last_stamp_ns, pair.stamp_j_ns);
      drift.first_stamp_ns = std::min(drift.first_stamp_ns, pair.stamp_i_ns);
      drift.last_stamp_ns = std::max(drift.last_stamp_ns, pair.stamp_j_ns);
      if (fit.diagnostics.inlier_mask.at(i)) {
        members.push_back(static_cast<int>(i));
      }
    }
    for (const auto& [segment, stretch] : stretches) {
      drift.stretches.push_back(stretch);
    }
    std::sort(drift.stretches.begin(),
              drift.stretches.end(),
              [](const ScaleStretch& a, const ScaleStretch& b) {
                return a.first_stamp_ns < b.first_stamp_ns;
              });
    std::vector<PairMetricScale> values;
    std::vector<double> times_s;
    for (const int i : members) {
      const MotionPair& pair = check->pairs[i];
      values.push_back(scales[i]);
      times_s.push_back(
          1e-9 *
          static_cast<double>((pair.stamp_i_ns - drift.first_stamp_ns) +
                              (pair.stamp_j_ns - drift.first_stamp_ns)) /
          2.0);
    }
    MeasureDrift(
        values,
        times_s,
        1e-9 * static_cast<double>(drift.last_stamp_ns - drift.first_stamp_ns),
        &drift);
    check->scale_drifts.push_back(std::move(drift));
  }
}

}  // namespace

bool ContradictsOdometry(const MotionPair& pair,
                         bool used,
                         const CalibrationResult& fit,
                         const CalibrationOptions& options) {
  if (used) return false;
  if (!fit.has_estimate) return true;
  const size_t segment = static_cast<size_t>(pair.segment);
  const double scale = segment < fit.metric_scales.size()
                           ? fit.metric_scales[segment]
                           : std::nan("");
  // A segment without a scale explains none of its pairs.
  return !(scale > 0.0) || !IsInlier(pair, fit.odom_from_cam, scale, options);
}

StretchCheckResult CalibrateWithStretchCheck(
    const MotionPairs& pairs,
    const CalibrationOptions& options,
    const StretchOptions& stretch_options) {
  StretchCheckResult check;
  check.pairs = pairs;
  for (size_t i = 0; i < pairs.size(); ++i) {
    check.input_pair_of_output.push_back(static_cast<int>(i));
  }
  for (int k = 0; k < NumSegments(pairs); ++k) {
    check.input_segment_of_output_segment.push_back(k);
  }
  check.result = CalibrateOdomCam(pairs, options);
  if (!check.result.has_estimate || !options.use_ransac) {
    check.contradicts_odometry =
        ContradictingPairs(check.pairs, check.result, options);
    return check;
  }
  check.stretches =
      FindContradictingRuns(pairs,
                            check.result.diagnostics.inlier_mask,
                            ContradictingPairs(pairs, check.result, options),
                            stretch_options.min_run_pairs);
  if (!check.stretches.empty())
    CutOutlierRuns(pairs, options, stretch_options, &check);
  if (stretch_options.check_scale_changes && check.result.has_estimate) {
    CutScaleChanges(options, stretch_options.scale_change, &check);
    if (!check.scale_changes.empty()) MeasureScaleDrifts(options, &check);
  }
  check.contradicts_odometry =
      ContradictingPairs(check.pairs, check.result, options);
  return check;
}

}  // namespace odomcal
