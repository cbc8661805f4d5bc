#include "odomcal/solver/camera_projection.h"

namespace odomcal {

const char* ProjectionModelName(ProjectionModel model) {
  switch (model) {
    case ProjectionModel::kSimplePinhole:
      return "SIMPLE_PINHOLE";
    case ProjectionModel::kPinhole:
      return "PINHOLE";
    case ProjectionModel::kSimpleRadial:
      return "SIMPLE_RADIAL";
    case ProjectionModel::kRadial:
      return "RADIAL";
    case ProjectionModel::kOpenCV:
      return "OPENCV";
  }
  return "UNKNOWN";
}

}  // namespace odomcal
