// Expectations shared by the tests of several cameras (rig_cli_test.cc,
// colmap_rig_cli_test.cc).
#pragma once

#include "odomcal/solver/angles.h"
#include "odomcal/solver/rigid3.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <iostream>
#include <string>
#include <vector>

namespace odomcal {

// Each error of a JSON odom_from_cam / camb_from_cama over its sigma:
// rotation (left perturbation: truth = Exp(e) * estimate) per axis, then
// translation x, y (and z unless z_held).
inline std::vector<double> NormalisedErrors(const Rigid3d& truth,
                                            const nlohmann::json& transform,
                                            const nlohmann::json& covariance,
                                            bool z_held) {
  const nlohmann::json& q = transform["quaternion_wxyz"];
  const Eigen::Quaterniond rotation(q[0].get<double>(),
                                    q[1].get<double>(),
                                    q[2].get<double>(),
                                    q[3].get<double>());
  const nlohmann::json& t = transform["translation_m"];
  const Eigen::Vector3d rotation_error =
      LogRotation(truth.rotation * rotation.inverse());
  const nlohmann::json& c = covariance["matrix"];
  std::vector<double> errors;
  for (int k = 0; k < 3; ++k) {
    errors.push_back(rotation_error(k) / std::sqrt(c[k][k].get<double>()));
  }
  for (int k = 0; k < (z_held ? 2 : 3); ++k) {
    errors.push_back((truth.translation(k) - t[k].get<double>()) /
                     std::sqrt(c[3 + k][3 + k].get<double>()));
  }
  return errors;
}

// Rotation error (left perturbation: truth = Exp(e) * estimate) and
// translation error of a JSON odom_from_cam / camb_from_cama, each within 3
// of its sigma. Prints each error over its sigma ("normalised error"), the
// numbers docs/cli.md quotes over seeds.
inline void ExpectWithinThreeSigma(const std::string& what,
                                   const Rigid3d& truth,
                                   const nlohmann::json& transform,
                                   const nlohmann::json& covariance,
                                   bool z_held) {
  const std::vector<double> errors =
      NormalisedErrors(truth, transform, covariance, z_held);
  for (size_t k = 0; k < errors.size(); ++k) {
    const std::string name =
        (k < 3 ? "r" : "t") + std::to_string(k < 3 ? k : k - 3);
    std::cout << "normalised error " << what << " " << name << " " << errors[k]
              << "\n";
    EXPECT_TRUE(std::isfinite(errors[k])) << name;  // a positive sigma
    EXPECT_LT(std::abs(errors[k]), 3.0) << name << " over its sigma";
  }
}

}  // namespace odomcal
