#include "odomcal/adapters/bag/camera_info_conversion.h"

#include "odomcal/adapters/format_error.h"

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

namespace odomcal::bag {
namespace {

[[noreturn]] void ThrowCameraInfoError(const std::string& context,
                                       const std::string& field,
                                       const std::string& problem) {
  throw FormatError(context + ": " + field + ": " + problem);
}

std::string DistortionText(const std::vector<double>& d) {
  std::string text = "[";
  for (size_t i = 0; i < d.size(); ++i) {
    char number[32];
    std::snprintf(number, sizeof(number), "%s%.6g", i == 0 ? "" : ", ", d[i]);
    text += number;
  }
  return text + "]";
}

bool AllZero(const std::vector<double>& values) {
  for (const double value : values) {
    if (value != 0.0) return false;
  }
  return true;
}

void CheckDistortionLength(const CameraInfoMessage& info,
                           const std::string& context,
                           size_t expected,
                           const char* names) {
  if (info.d.size() != expected) {
    ThrowCameraInfoError(
        context,
        "D",
        "distortion_model '" + info.distortion_model + "' needs " +
            std::to_string(expected) + " coefficients (" + names + "), got " +
            std::to_string(info.d.size()) + " " + DistortionText(info.d));
  }
}

// The shortest of %.15g, %.16g, %.17g that reads back to `value`.
std::string ExactDecimal(double value) {
  char text[40];
  for (const int digits : {15, 16, 17}) {
    std::snprintf(text, sizeof(text), "%.*g", digits, value);
    if (std::strtod(text, nullptr) == value) break;
  }
  return text;
}

}  // namespace

ColmapCamera ColmapCameraFromCameraInfo(const CameraInfoMessage& info,
                                        const std::string& context) {
  const RegionOfInterest& roi = info.roi;
  if (info.width == 0 || info.height == 0) {
    ThrowCameraInfoError(context,
                         "width/height",
                         "the image size is " + std::to_string(info.width) +
                             " x " + std::to_string(info.height) +
                             " (the camera was never calibrated?)");
  }
  if (info.binning_x > 1 || info.binning_y > 1) {
    ThrowCameraInfoError(context,
                         "binning_x/binning_y",
                         "binning " + std::to_string(info.binning_x) + " x " +
                             std::to_string(info.binning_y) +
                             " is not supported (only 0 or 1: the images "
                             "must have the calibrated resolution)");
  }
  const bool roi_full_image =
      roi.x_offset == 0 && roi.y_offset == 0 &&
      ((roi.width == 0 && roi.height == 0) ||
       (roi.width == info.width && roi.height == info.height));
  if (!roi_full_image) {
    ThrowCameraInfoError(
        context,
        "roi",
        "a region of interest (x_offset " + std::to_string(roi.x_offset) +
            ", y_offset " + std::to_string(roi.y_offset) + ", " +
            std::to_string(roi.width) + " x " + std::to_string(roi.height) +
            ") is not supported; record the full image");
  }
  for (const double value : info.k) {
    if (!std::isfinite(value)) {
      ThrowCameraInfoError(context, "K", "holds a value that is not finite");
    }
  }
  for (const double value : info.d) {
    if (!std::isfinite(value)) {
      ThrowCameraInfoError(context, "D", "holds a value that is not finite");
    }
  }
  const double fx = info.k[0];
  const double fy = info.k[4];
  if (!(fx > 0.0) || !(fy > 0.0)) {
    ThrowCameraInfoError(context,
                         "K",
                         "focal lengths fx = K[0] = " + std::to_string(fx) +
                             " and fy = K[4] = " + std::to_string(fy) +
                             " must be positive (an uncalibrated camera?)");
  }
  if (info.k[1] != 0.0 || info.k[3] != 0.0 || info.k[6] != 0.0 ||
      info.k[7] != 0.0 || info.k[8] != 1.0) {
    ThrowCameraInfoError(context,
                         "K",
                         "is not [fx 0 cx; 0 fy cy; 0 0 1] (skew or a "
                         "scaled last row is not supported)");
  }
  // The pixel-centre shift, see the header.
  const double cx = info.k[2] + 0.5;
  const double cy = info.k[5] + 0.5;

  ColmapCamera camera;
  camera.camera_id = 1;
  camera.width = info.width;
  camera.height = info.height;
  camera.params = {fx, fy, cx, cy};
  const std::string& model = info.distortion_model;
  if (model == "equidistant" && (info.d.empty() || AllZero(info.d))) {
    // Still a fisheye: without coefficients r = f * theta, not f * tan(theta).
    camera.model = ColmapCameraModel::kOpenCVFisheye;
    camera.params.insert(camera.params.end(), {0.0, 0.0, 0.0, 0.0});
  } else if (info.d.empty() || AllZero(info.d)) {
    if (model != "plumb_bob" && model != "rational_polynomial" &&
        !model.empty()) {
      ThrowCameraInfoError(context,
                           "distortion_model",
                           "unknown model '" + model +
                               "' (known: plumb_bob, rational_polynomial, "
                               "equidistant)");
    }
    camera.model = ColmapCameraModel::kPinhole;
  } else if (model == "plumb_bob") {
    CheckDistortionLength(info, context, 5, "k1 k2 p1 p2 k3");
    if (info.d[4] == 0.0) {
      camera.model = ColmapCameraModel::kOpenCV;
      camera.params.insert(
          camera.params.end(), info.d.begin(), info.d.begin() + 4);
    } else {
      camera.model = ColmapCameraModel::kFullOpenCV;
      camera.params.insert(camera.params.end(), info.d.begin(), info.d.end());
      camera.params.insert(camera.params.end(), {0.0, 0.0, 0.0});
    }
  } else if (model == "rational_polynomial") {
    CheckDistortionLength(info, context, 8, "k1 k2 p1 p2 k3 k4 k5 k6");
    camera.model = ColmapCameraModel::kFullOpenCV;
    camera.params.insert(camera.params.end(), info.d.begin(), info.d.end());
  } else if (model == "equidistant") {
    CheckDistortionLength(info, context, 4, "k1 k2 k3 k4");
    camera.model = ColmapCameraModel::kOpenCVFisheye;
    camera.params.insert(camera.params.end(), info.d.begin(), info.d.end());
  } else {
    ThrowCameraInfoError(context,
                         "distortion_model",
                         "unknown model '" + model +
                             "' (known: plumb_bob, rational_polynomial, "
                             "equidistant)");
  }
  return camera;
}

void CheckCameraInfoImageSize(const CameraInfoMessage& info,
                              uint32_t image_width,
                              uint32_t image_height,
                              const std::string& context) {
  if (info.width != image_width || info.height != image_height) {
    ThrowCameraInfoError(
        context,
        "width/height",
        "the calibration is for " + std::to_string(info.width) + " x " +
            std::to_string(info.height) + " images, but the images are " +
            std::to_string(image_width) + " x " + std::to_string(image_height));
  }
}

std::string ColmapCameraLine(const ColmapCamera& camera) {
  std::string line = std::to_string(camera.camera_id) + " " +
                     ColmapCameraModelName(camera.model) + " " +
                     std::to_string(camera.width) + " " +
                     std::to_string(camera.height);
  for (const double value : camera.params) line += " " + ExactDecimal(value);
  return line;
}

std::string OdomcalCameraFlags(const ColmapCamera& camera) {
  std::string flags = std::string("--camera_model ") +
                      ColmapCameraModelName(camera.model) + " --camera_params ";
  for (size_t i = 0; i < camera.params.size(); ++i) {
    flags += (i == 0 ? "" : ",") + ExactDecimal(camera.params[i]);
  }
  return flags;
}

}  // namespace odomcal::bag
