// A road-like outdoor scene for the renderer: a car's forward camera on a
// road of straights and two turns, for the presets `road` and `road_sloped`
// (dataset_presets.h).
//
// The route (the car's path, in the `room` frame, metres, z up) starts at the
// origin heading +x: a straight, a left arc, a straight, a right arc and a
// last straight, at one constant speed. The road is road_width_m wide, its
// centre line lane_offset_m left of the route (the car keeps to the right
// lane). The ground is z = f(x) + g(y), f and g piecewise linear with knots
// every ground_cell_m, their slopes slope_x_deg * sin(2 pi x / wavelength)
// and slope_y_deg * cos(2 pi y / wavelength) (flat when both are 0): so the
// ground is exactly tiled by planar parallelograms, one per cell, and a car
// driving along x pitches with f and banks with g (along y the other way
// round). Around the route: posts just off the road, building facades set
// back behind the road edges with gaps between them, ground to margin_m
// beyond the route on every side, ending at far walls (a distant
// background); the sky is the render's background colour.
//
// Textures: the road is asphalt of low contrast with sparse high-contrast
// patches (road_patch_fraction of the road's area) and dashed centre and
// solid edge markings; the ground beside it has moderate contrast; both are
// functions of the position (continuous across tiles). Facades, posts and
// far walls carry the room scenes' value noise (value_noise.h).
#pragma once

#include "odomcal/datasets/rendering/room_scene.h"
#include "odomcal/datasets/simulation/unicycle_path.h"
#include "odomcal/solver/planar_pose.h"
#include "odomcal/solver/rigid3.h"

#include <Eigen/Core>

#include <cstdint>
#include <vector>

namespace odomcal {

struct RoadOptions {
  // The route.
  double speed_mps = 7.0;
  double first_straight_m = 15.0;
  double turn_radius_m = 15.0;
  double left_turn_deg = 60.0;
  double middle_straight_m = 10.0;
  double right_turn_deg = 60.0;
  double last_straight_m = 40.0;  // the scene is built along all of it
  // The road and the ground.
  double road_width_m = 7.0;
  double lane_offset_m = 1.75;
  double ground_cell_m = 5.0;
  double slope_x_deg = 0.0;  // amplitude of the ground's slope along x
  double slope_y_deg = 0.0;  // along y
  double slope_wavelength_m = 60.0;
  double margin_m = 45.0;  // ground beyond the route, then the far walls
  double far_wall_height_m = 12.0;
  // Roadside structures, set back from the nearer road edge.
  double post_setback_m = 1.0;
  double post_spacing_m = 12.0;
  double post_height_m = 3.0;
  double facade_min_setback_m = 3.0;
  double facade_max_setback_m = 9.0;
  double facade_length_m = 10.0;  // mean; each 0.6-1.4 times this
  double facade_gap_m = 8.0;      // mean gap between facades along the road
  double facade_min_height_m = 4.0;
  double facade_max_height_m = 12.0;
  // Textures.
  double road_texel_size_m = 0.02;
  double ground_texel_size_m = 0.08;
  double structure_texel_size_m = 0.04;
  double far_texel_size_m = 0.15;
  double road_contrast = 0.02;  // asphalt outside the patches
  double road_patch_fraction = 0.05;
  double road_patch_contrast = 0.25;
  double ground_contrast = 0.12;
  void Check() const;  // throws std::invalid_argument naming the field
};

// One piece of the route: from `start`, length_m along an arc of signed
// curvature (1/m, > 0 turning left; 0 straight).
struct RoutePiece {
  PlanarPose start;
  double length_m = 0.0;
  double curvature = 0.0;
};

std::vector<RoutePiece> RoadRoute(const RoadOptions& options);

// The route driven at speed_mps from path time 0: a UnicyclePath of one
// manoeuvre per piece. Throws std::invalid_argument when the route is
// shorter than duration_s at that speed.
UnicyclePath MakeRoadPath(const RoadOptions& options, double duration_s);

// The ground z = f(x) + g(y) over a rectangle of whole cells.
class RoadGround {
 public:
  RoadGround() = default;
  RoadGround(const Eigen::Vector2d& min_xy,
             double cell_m,
             std::vector<double> f_knots,
             std::vector<double> g_knots);

  double Height(const Eigen::Vector2d& p) const;
  // (df/dx, dg/dy) of the cell holding p (the cell to the +x / +y side on
  // a knot).
  Eigen::Vector2d Gradient(const Eigen::Vector2d& p) const;
  Eigen::Vector2d min_xy() const { return min_xy_; }
  Eigen::Vector2d max_xy() const;
  double cell_m() const { return cell_m_; }
  int num_cells_x() const { return static_cast<int>(f_.size()) - 1; }
  int num_cells_y() const { return static_cast<int>(g_.size()) - 1; }

 private:
  double F(double x, double* slope) const;
  double G(double y, double* slope) const;
  Eigen::Vector2d min_xy_ = Eigen::Vector2d::Zero();
  double cell_m_ = 1.0;
  std::vector<double> f_ = {0.0, 0.0}, g_ = {0.0, 0.0};
};

// The ground under the whole route and margin_m around it.
RoadGround MakeRoadGround(const RoadOptions& options);

// room_from_odom of a car at the planar pose: on the ground at (x, y), its z
// axis the ground's normal there, its x axis the heading lifted onto the
// ground (the direction the car moves in: no side slip).
Rigid3d PoseOnGround(const RoadGround& ground, const PlanarPose& pose);

// Surfaces and textures (see above); scene.seed seeds the textures and the
// placement of structures, scene.num_threads generate the textures.
RoomScene BuildRoadScene(const RoadOptions& options,
                         const RoomSceneOptions& scene);

}  // namespace odomcal
