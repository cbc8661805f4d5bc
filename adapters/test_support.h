// Helpers shared by the adapters' unit tests and tests/ (not installed).
#pragma once

#include "odomcal/adapters/colmap_model.h"
#include "odomcal/adapters/format_error.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <functional>
#include <string>
#include <utility>
#include <vector>

namespace odomcal {

// The FormatError message thrown by `action`, or "" (and a test failure) if
// it throws none.
inline std::string FormatErrorOf(const std::function<void()>& action) {
  try {
    action();
  } catch (const FormatError& error) {
    return error.what();
  }
  ADD_FAILURE() << "no FormatError thrown";
  return "";
}

inline ColmapCamera MakeColmapCamera(uint32_t camera_id,
                                     ColmapCameraModel model,
                                     int width,
                                     int height,
                                     std::vector<double> params) {
  ColmapCamera camera;
  camera.camera_id = camera_id;
  camera.model = model;
  camera.width = width;
  camera.height = height;
  camera.params = std::move(params);
  return camera;
}

inline bool Contains(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

}  // namespace odomcal
