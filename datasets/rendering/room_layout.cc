// Clearance and ray distance are brute force over all segments (tens of
// them); the planner calls them a few thousand times per path.

#include "odomcal/datasets/rendering/room_layout.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

namespace odomcal {
namespace {

double PointSegmentDistance(const Eigen::Vector2d& p,
                            const Eigen::Vector2d& a,
                            const Eigen::Vector2d& b) {
  const Eigen::Vector2d ab = b - a;
  const double t = std::clamp((p - a).dot(ab) / ab.squaredNorm(), 0.0, 1.0);
  return (a + t * ab - p).norm();
}

// Distance along `dir` from p to segment ab, infinity when missed.
double RaySegmentDistance(const Eigen::Vector2d& p,
                          const Eigen::Vector2d& dir,
                          const Eigen::Vector2d& a,
                          const Eigen::Vector2d& b) {
  const Eigen::Vector2d ab = b - a;
  const double denom = dir.x() * ab.y() - dir.y() * ab.x();
  if (std::abs(denom) < 1e-12) return std::numeric_limits<double>::infinity();
  const Eigen::Vector2d ap = a - p;
  const double t = (ap.x() * ab.y() - ap.y() * ab.x()) / denom;
  const double s = (ap.x() * dir.y() - ap.y() * dir.x()) / denom;
  if (t < 0.0 || s < 0.0 || s > 1.0)
    return std::numeric_limits<double>::infinity();
  return t;
}

bool InsideConvex(const Eigen::Vector2d& p,
                  const std::vector<Eigen::Vector2d>& poly) {
  for (size_t i = 0; i < poly.size(); ++i) {
    const Eigen::Vector2d e = poly[(i + 1) % poly.size()] - poly[i];
    const Eigen::Vector2d q = p - poly[i];
    if (e.x() * q.y() - e.y() * q.x() < 0.0) return false;
  }
  return true;
}

}  // namespace

std::vector<Eigen::Vector2d> BoxSpec::Footprint() const {
  const double c = std::cos(yaw_rad), s = std::sin(yaw_rad);
  const Eigen::Vector2d ax(c, s), ay(-s, c);
  const double hx = 0.5 * size_m.x(), hy = 0.5 * size_m.y();
  return {center_xy - hx * ax - hy * ay,
          center_xy + hx * ax - hy * ay,
          center_xy + hx * ax + hy * ay,
          center_xy - hx * ax + hy * ay};
}

double RoomLayout::DistanceToObstacles(const Eigen::Vector2d& p) const {
  double best = std::numeric_limits<double>::infinity();
  for (const WallSpec& wall : walls) {
    best = std::min(best, PointSegmentDistance(p, wall.from, wall.to));
  }
  for (const BoxSpec& box : boxes) {
    const std::vector<Eigen::Vector2d> corners = box.Footprint();
    if (InsideConvex(p, corners)) return 0.0;
    for (size_t i = 0; i < 4; ++i) {
      best = std::min(
          best, PointSegmentDistance(p, corners[i], corners[(i + 1) % 4]));
    }
  }
  return best;
}

double RoomLayout::RayDistance(const Eigen::Vector2d& p,
                               const Eigen::Vector2d& dir) const {
  double best = std::numeric_limits<double>::infinity();
  for (const WallSpec& wall : walls) {
    best = std::min(best, RaySegmentDistance(p, dir, wall.from, wall.to));
  }
  for (const BoxSpec& box : boxes) {
    const std::vector<Eigen::Vector2d> corners = box.Footprint();
    for (size_t i = 0; i < 4; ++i) {
      best = std::min(
          best, RaySegmentDistance(p, dir, corners[i], corners[(i + 1) % 4]));
    }
  }
  return best;
}

void RoomLayout::Check() const {
  if (floors.empty()) throw std::invalid_argument("RoomLayout: no floor patch");
  if (!(std::abs(floor_slope_deg) < 30.0) ||
      !std::isfinite(floor_slope_pivot_x_m)) {
    throw std::invalid_argument(
        "RoomLayout.floor_slope_deg must be within (-30, 30) and its pivot "
        "finite");
  }
  for (size_t i = 0; i < floors.size(); ++i) {
    if (!((floors[i].max_xy - floors[i].min_xy).minCoeff() > 0.0)) {
      throw std::invalid_argument("RoomLayout.floors[" + std::to_string(i) +
                                  "]: empty rectangle");
    }
  }
  for (size_t i = 0; i < walls.size(); ++i) {
    if (!((walls[i].to - walls[i].from).norm() > 1e-6) ||
        !(walls[i].height_m > 0.0)) {
      throw std::invalid_argument("RoomLayout.walls[" + std::to_string(i) +
                                  "]: zero length or height");
    }
  }
  for (size_t i = 0; i < boxes.size(); ++i) {
    if (!(boxes[i].size_m.minCoeff() > 0.0)) {
      throw std::invalid_argument("RoomLayout.boxes[" + std::to_string(i) +
                                  "]: size must be positive");
    }
  }
  if (ceiling_height_m && !(*ceiling_height_m > 0.0)) {
    throw std::invalid_argument("RoomLayout.ceiling_height_m must be > 0");
  }
}

RoomLayout MakeRectangularRoom(double length_m,
                               double width_m,
                               double height_m,
                               bool ceiling,
                               const std::vector<BoxSpec>& boxes) {
  RoomLayout layout;
  layout.floors.push_back(
      {Eigen::Vector2d(0, 0), Eigen::Vector2d(length_m, width_m), true});
  const Eigen::Vector2d c00(0, 0), c10(length_m, 0), c11(length_m, width_m),
      c01(0, width_m);
  layout.walls = {{c00, c10, height_m, true},
                  {c10, c11, height_m, true},
                  {c11, c01, height_m, true},
                  {c01, c00, height_m, true}};
  layout.boxes = boxes;
  if (ceiling) layout.ceiling_height_m = height_m;
  layout.Check();
  return layout;
}

RoomLayout MakeTwoRoomsWithCorridor(double height_m,
                                    bool ceiling,
                                    bool textured_corridor) {
  using V = Eigen::Vector2d;
  RoomLayout layout;
  const auto wall = [&](const V& a, const V& b, bool textured) {
    layout.walls.push_back({a, b, height_m, textured});
  };
  // Room A.
  layout.floors.push_back({V(0, 0), V(5.0, 4.5), true});
  wall(V(0, 0), V(5.0, 0), true);
  wall(V(5.0, 0), V(5.0, 4.5), true);
  wall(V(0, 4.5), V(0, 0), true);
  wall(V(3.8, 4.5), V(0, 4.5), true);  // door at x in [3.8, 5.0]
  // Room B.
  layout.floors.push_back({V(5.2, 0), V(10.2, 4.5), true});
  wall(V(5.2, 0), V(10.2, 0), true);
  wall(V(10.2, 0), V(10.2, 4.5), true);
  wall(V(10.2, 4.5), V(6.4, 4.5), true);  // door at x in [5.2, 6.4]
  wall(V(5.2, 4.5), V(5.2, 0), true);
  // Corridor: flat colour on every surface, so its views have no features
  // (unless textured_corridor).
  const bool t = textured_corridor;
  layout.floors.push_back({V(3.8, 4.5), V(5.0, 5.1), t});
  layout.floors.push_back({V(3.8, 5.1), V(6.4, 6.3), t});
  layout.floors.push_back({V(5.2, 4.5), V(6.4, 5.1), t});
  wall(V(3.8, 4.5), V(3.8, 6.3), t);
  wall(V(3.8, 6.3), V(6.4, 6.3), t);
  wall(V(6.4, 6.3), V(6.4, 4.5), t);
  wall(V(5.0, 4.5), V(5.0, 5.1), t);
  wall(V(5.0, 5.1), V(5.2, 5.1), t);
  wall(V(5.2, 5.1), V(5.2, 4.5), t);
  // Parallax near the walls, away from the corridor route.
  layout.boxes = {
      {V(0.9, 0.9), 0.35, Eigen::Vector3d(0.8, 0.6, 0.7), true},
      {V(1.3, 3.7), 0.0, Eigen::Vector3d(0.35, 0.35, height_m), true},
      {V(4.3, 0.7), -0.2, Eigen::Vector3d(0.7, 0.5, 1.0), true},
      {V(9.3, 0.9), -0.3, Eigen::Vector3d(0.8, 0.6, 0.8), true},
      {V(9.4, 3.6), 0.0, Eigen::Vector3d(0.35, 0.35, height_m), true},
      {V(6.3, 0.8), 0.25, Eigen::Vector3d(0.6, 0.6, 0.5), true},
  };
  if (ceiling) layout.ceiling_height_m = height_m;
  layout.Check();
  return layout;
}

std::vector<Eigen::Vector2d> TwoRoomsCorridorWaypoints() {
  return {Eigen::Vector2d(4.4, 3.8),
          Eigen::Vector2d(4.4, 5.7),
          Eigen::Vector2d(5.8, 5.7),
          Eigen::Vector2d(5.8, 3.8)};
}

}  // namespace odomcal
