// The geometry of a rendered environment, in the `room` frame (metres, z up,
// floor at z = 0): floor patches, vertical walls, boxes standing on the
// floor, and an optional ceiling over every floor patch. Anything may be
// marked featureless (one flat colour) instead of textured.
//
// The layout is also the path planner's map: seen from above, walls are 2D
// segments and boxes are rectangles, and DistanceToObstacles() is the
// clearance of a point. RoomScene (room_scene.h) turns a layout into
// textured surfaces.
#pragma once

#include <Eigen/Core>

#include <optional>
#include <vector>

namespace odomcal {

struct FloorPatch {
  Eigen::Vector2d min_xy = Eigen::Vector2d::Zero();  // axis-aligned rectangle
  Eigen::Vector2d max_xy = Eigen::Vector2d::Ones();
  bool textured = true;
};

// A vertical wall from the floor up to height_m along the segment from-to.
struct WallSpec {
  Eigen::Vector2d from = Eigen::Vector2d::Zero();
  Eigen::Vector2d to = Eigen::Vector2d::UnitX();
  double height_m = 2.5;
  bool textured = true;
};

// A box on the floor: centre (x, y), rotated by yaw about +z, with size
// (length along its x, width along its y, height). A pillar is a tall box.
struct BoxSpec {
  Eigen::Vector2d center_xy = Eigen::Vector2d::Zero();
  double yaw_rad = 0.0;
  Eigen::Vector3d size_m = Eigen::Vector3d(0.5, 0.5, 0.5);
  bool textured = true;

  // The four footprint corners, counter-clockwise.
  std::vector<Eigen::Vector2d> Footprint() const;
};

struct RoomLayout {
  std::vector<FloorPatch> floors;
  std::vector<WallSpec> walls;
  std::vector<BoxSpec> boxes;
  std::optional<double> ceiling_height_m;  // none: open to a black sky
  // The floor patches (not the walls, boxes or the plane the robot drives
  // in, z = 0) tilted by this about the line y-parallel through
  // x = floor_slope_pivot_x_m: a floor sloped against the driven plane, for
  // the floor-plane check. Within (-30, 30) degrees.
  double floor_slope_deg = 0.0;
  double floor_slope_pivot_x_m = 0.0;

  // Distance from `p` to the nearest wall segment or box outline (0 inside a
  // box), seen from above.
  double DistanceToObstacles(const Eigen::Vector2d& p) const;

  // Distance from `p` along the unit direction `dir` to the first wall or box
  // outline; infinity when nothing is hit.
  double RayDistance(const Eigen::Vector2d& p,
                     const Eigen::Vector2d& dir) const;

  // Throws std::invalid_argument for empty layouts, degenerate walls, floors
  // or boxes, or a non-positive ceiling height.
  void Check() const;
};

// A closed rectangular room [0, length] x [0, width] with walls of `height_m`,
// the boxes given, and a ceiling at height_m when `ceiling`.
RoomLayout MakeRectangularRoom(double length_m,
                               double width_m,
                               double height_m,
                               bool ceiling,
                               const std::vector<BoxSpec>& boxes);

// Two textured 5 x 4.5 m rooms side by side, A = [0, 5] x [0, 4.5] and
// B = [5.2, 10.2] x [0, 4.5], joined by a featureless 1.2 m wide corridor
// that leaves A northwards at x in [3.8, 5.0], runs east at y in [5.1, 6.3]
// and enters B at x in [5.2, 6.4]. Both doors lie on the line y = 4.5, so no
// straight line of sight joins the rooms: every view of A and every view of
// B are separated by views of the flat-coloured corridor. Used by the `hard`
// preset to split the reconstruction in two.
RoomLayout MakeTwoRoomsWithCorridor(double height_m,
                                    bool ceiling,
                                    bool textured_corridor = false);

// Centre-line waypoints through that corridor, from inside A to inside B.
std::vector<Eigen::Vector2d> TwoRoomsCorridorWaypoints();

}  // namespace odomcal
