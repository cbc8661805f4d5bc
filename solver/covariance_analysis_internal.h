// The calibration's covariance and observability verdict from the Fisher
// information (step 5 of calibrate.h); internal: not installed.
#pragma once

#include "odomcal/solver/calibration_options.h"
#include "odomcal/solver/calibration_result.h"

#include <Eigen/Core>

#include <optional>
#include <vector>

namespace odomcal::internal {

// The inverse of an information matrix, or nothing when it is (numerically)
// singular: eigenvalues of the diagonally normalised matrix below
// kNullSpaceTolerance of the largest.
std::optional<Eigen::MatrixXd> InvertInformation(
    const Eigen::MatrixXd& information);

// Covariance, standard deviations and the observability verdict from the
// information matrix in [rx, ry, rz, tx, ty, s_k..., tz if estimated or under
// its prior (result->translation_z_prior.moved_by_data)] order.
// Quantities whose standard deviation exceeds the options' limits, or that
// take part in a null direction of the information, become undetermined in
// result->observability.
void AnalyseInformation(const Eigen::MatrixXd& information,
                        const std::vector<int>& segments,
                        int num_segments,
                        const CalibrationOptions& options,
                        CalibrationResult* result);

}  // namespace odomcal::internal
