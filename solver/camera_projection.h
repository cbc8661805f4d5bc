// The projection of COLMAP's perspective camera models, templated for
// Ceres' automatic differentiation. Parameters are in COLMAP's order and the
// projection is COLMAP's (src/colmap/sensor/models.h): normalise by z, add
// the distortion to the normalised coordinates, then scale by the focal
// length and add the principal point. The pixel convention is the
// parameters': COLMAP's principal points and keypoints put the centre of the
// top-left pixel at (0.5, 0.5), so a model read from COLMAP projects into
// COLMAP's keypoint coordinates without any shift.
//
//   kSimplePinhole 3 (f, cx, cy)
//   kPinhole       4 (fx, fy, cx, cy)
//   kSimpleRadial  4 (f, cx, cy, k)          radial = k r^2
//   kRadial        5 (f, cx, cy, k1, k2)     radial = k1 r^2 + k2 r^4
//   kOpenCV        8 (fx, fy, cx, cy, k1, k2, p1, p2)
//                  radial as kRadial; tangential
//                  du = 2 p1 u v + p2 (r^2 + 2 u^2),
//                  dv = p1 (r^2 + 2 v^2) + 2 p2 u v
#pragma once

#include <array>
#include <type_traits>

namespace odomcal {

enum class ProjectionModel {
  kSimplePinhole,
  kPinhole,
  kSimpleRadial,
  kRadial,
  kOpenCV,
};

constexpr int kMaxProjectionParams = 8;

// Number of parameters of `model` (above).
constexpr int ProjectionNumParams(ProjectionModel model) {
  switch (model) {
    case ProjectionModel::kSimplePinhole:
      return 3;
    case ProjectionModel::kPinhole:
    case ProjectionModel::kSimpleRadial:
      return 4;
    case ProjectionModel::kRadial:
      return 5;
    case ProjectionModel::kOpenCV:
      return 8;
  }
  return 0;
}

// COLMAP's name of the model, e.g. "SIMPLE_RADIAL".
const char* ProjectionModelName(ProjectionModel model);

// The index of cx in the parameters (cy follows it).
constexpr int PrincipalPointIndex(ProjectionModel model) {
  return model == ProjectionModel::kPinhole || model == ProjectionModel::kOpenCV
             ? 2
             : 1;
}

// Pixel coordinates of the camera-frame point (x, y, z), z > 0. False
// (pixel untouched) for a point on or behind the camera plane.
template <ProjectionModel kModel, typename T>
bool ProjectToPixel(const T* params, const T* point_in_cam, T* pixel) {
  const T& z = point_in_cam[2];
  if (!(z > T(0))) return false;
  const T u = point_in_cam[0] / z;
  const T v = point_in_cam[1] / z;
  T du = T(0);
  T dv = T(0);
  T fx, fy, cx, cy;
  if constexpr (kModel == ProjectionModel::kSimplePinhole ||
                kModel == ProjectionModel::kSimpleRadial ||
                kModel == ProjectionModel::kRadial) {
    fx = params[0];
    fy = params[0];
    cx = params[1];
    cy = params[2];
  } else {
    fx = params[0];
    fy = params[1];
    cx = params[2];
    cy = params[3];
  }
  const T r2 = u * u + v * v;
  if constexpr (kModel == ProjectionModel::kSimpleRadial) {
    const T radial = params[3] * r2;
    du = u * radial;
    dv = v * radial;
  } else if constexpr (kModel == ProjectionModel::kRadial) {
    const T radial = params[3] * r2 + params[4] * r2 * r2;
    du = u * radial;
    dv = v * radial;
  } else if constexpr (kModel == ProjectionModel::kOpenCV) {
    const T radial = params[4] * r2 + params[5] * r2 * r2;
    const T uv = u * v;
    du = u * radial + T(2) * params[6] * uv + params[7] * (r2 + T(2) * u * u);
    dv = v * radial + T(2) * params[7] * uv + params[6] * (r2 + T(2) * v * v);
  }
  pixel[0] = fx * (u + du) + cx;
  pixel[1] = fy * (v + dv) + cy;
  return true;
}

// Calls visitor(std::integral_constant<ProjectionModel, kModel>()) for a
// model known only at run time, so that one switch serves every templated
// use (ProjectToPixel<kModel>, cost functions of kModel). A value outside
// the enum gives the visitor's result type value-initialised.
template <typename Visitor>
auto VisitProjectionModel(ProjectionModel model, Visitor&& visitor) {
  using M = ProjectionModel;
  switch (model) {
    case M::kSimplePinhole:
      return visitor(std::integral_constant<M, M::kSimplePinhole>());
    case M::kPinhole:
      return visitor(std::integral_constant<M, M::kPinhole>());
    case M::kSimpleRadial:
      return visitor(std::integral_constant<M, M::kSimpleRadial>());
    case M::kRadial:
      return visitor(std::integral_constant<M, M::kRadial>());
    case M::kOpenCV:
      return visitor(std::integral_constant<M, M::kOpenCV>());
  }
  return decltype(visitor(std::integral_constant<M, M::kPinhole>())){};
}

}  // namespace odomcal
