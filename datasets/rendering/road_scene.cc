// The ground is one parallelogram per cell, textured procedurally from the
// position of each texel (the road's lateral offset and distance along the
// route, hash-based value noise), so that textures continue across cells.
// Structures are placed walking along the route with one seeded generator;
// their value-noise textures, like the ground's, are generated on
// scene.num_threads threads, each texture independent of the others.

#include "odomcal/datasets/rendering/road_scene.h"

#include "odomcal/adapters/timestamp.h"
#include "odomcal/datasets/rendering/value_noise.h"
#include "odomcal/datasets/simulation/seed.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <optional>
#include <random>
#include <stdexcept>
#include <string>
#include <thread>

namespace odomcal {
namespace {

constexpr double kDegToRad = M_PI / 180.0;

void Require(bool condition, const std::string& what) {
  if (!condition) throw std::invalid_argument("RoadOptions." + what);
}

// Where a point lies relative to the route: distance along it and signed
// lateral offset (m, > 0 to the left of the direction of travel).
struct RouteCoordinates {
  double along_m = 0.0;
  double left_m = std::numeric_limits<double>::infinity();
};

RouteCoordinates ToRouteCoordinates(const std::vector<RoutePiece>& route,
                                    const Eigen::Vector2d& p) {
  RouteCoordinates best;
  double start_s = 0.0;
  for (size_t i = 0; i < route.size(); ++i) {
    const RoutePiece& piece = route[i];
    const Eigen::Vector2d o(piece.start.x, piece.start.y);
    const Eigen::Vector2d heading(std::cos(piece.start.yaw_rad),
                                  std::sin(piece.start.yaw_rad));
    const Eigen::Vector2d left(-heading.y(), heading.x());
    RouteCoordinates here;
    bool inside = false;
    if (piece.curvature == 0.0) {
      const double a = (p - o).dot(heading);
      // The first and last straights extend beyond the route's ends.
      inside = (a >= 0.0 || i == 0) &&
               (a <= piece.length_m || i + 1 == route.size());
      here = {start_s + a, (p - o).dot(left)};
    } else {
      const double radius = 1.0 / std::abs(piece.curvature);
      const double side = piece.curvature > 0.0 ? 1.0 : -1.0;
      const Eigen::Vector2d centre = o + side * radius * left;
      const Eigen::Vector2d from_centre = p - centre;
      const Eigen::Vector2d start_dir = o - centre;
      // Angle from the start radius, in the direction of travel.
      const double cross =
          start_dir.x() * from_centre.y() - start_dir.y() * from_centre.x();
      const double angle = side * std::atan2(cross, start_dir.dot(from_centre));
      inside = angle >= 0.0 && angle * radius <= piece.length_m;
      here = {start_s + angle * radius, side * (radius - from_centre.norm())};
    }
    if (inside && std::abs(here.left_m) < std::abs(best.left_m)) best = here;
    start_s += piece.length_m;
  }
  return best;
}

PlanarPose RoutePoseAt(const std::vector<RoutePiece>& route, double s) {
  for (size_t i = 0; i < route.size(); ++i) {
    if (s <= route[i].length_m || i + 1 == route.size()) {
      const double w = route[i].curvature;
      return UnicycleStep(route[i].start, 1.0, w, s);
    }
    s -= route[i].length_m;
  }
  return PlanarPose();
}

uint64_t Hash(uint64_t seed, int64_t i, int64_t j) {
  return DeriveSeed(DeriveSeed(seed, static_cast<uint64_t>(i)),
                    static_cast<uint64_t>(j));
}

double HashUnit(uint64_t seed, int64_t i, int64_t j) {  // in [0, 1)
  return (Hash(seed, i, j) >> 11) * (1.0 / 9007199254740992.0);
}

// Value noise at a position: octaves of period min_period_m ... max (doubling),
// each smoothstep-interpolated lattice values in [-1, 1], averaged.
double PositionNoise(const Eigen::Vector2d& p,
                     double min_period_m,
                     double max_period_m,
                     uint64_t seed) {
  double sum = 0.0;
  int octaves = 0;
  for (double period = min_period_m; period <= max_period_m * 1.0001;
       period *= 2.0, ++octaves) {
    const uint64_t octave_seed = DeriveSeed(seed, octaves);
    const double x = p.x() / period, y = p.y() / period;
    const double fx = std::floor(x), fy = std::floor(y);
    const int64_t ix = static_cast<int64_t>(fx), iy = static_cast<int64_t>(fy);
    const auto smooth = [](double t) { return t * t * (3.0 - 2.0 * t); };
    const double tx = smooth(x - fx), ty = smooth(y - fy);
    const auto value = [&](int64_t a, int64_t b) {
      return 2.0 * HashUnit(octave_seed, a, b) - 1.0;
    };
    const double v0 = value(ix, iy) * (1 - tx) + value(ix + 1, iy) * tx;
    const double v1 = value(ix, iy + 1) * (1 - tx) + value(ix + 1, iy + 1) * tx;
    sum += v0 * (1 - ty) + v1 * ty;
  }
  return octaves > 0 ? sum / std::sqrt(static_cast<double>(octaves)) : 0.0;
}

struct GroundLook {
  const RoadOptions* options;
  const std::vector<RoutePiece>* route;
  uint64_t seed;

  // 1 inside a patch of the asphalt: at most one disc per 2 x 2 m cell,
  // present with a probability that covers road_patch_fraction of the area.
  double PatchMask(const Eigen::Vector2d& p) const {
    constexpr double kCell = 2.0, kMinRadius = 0.15, kMaxRadius = 0.6;
    const double mean_area =
        M_PI *
        (kMinRadius * kMinRadius + kMinRadius * kMaxRadius +
         kMaxRadius * kMaxRadius) /
        3.0;
    const double probability =
        std::min(1.0, options->road_patch_fraction * kCell * kCell / mean_area);
    const int64_t i = static_cast<int64_t>(std::floor(p.x() / kCell));
    const int64_t j = static_cast<int64_t>(std::floor(p.y() / kCell));
    const uint64_t cell_seed = Hash(DeriveSeed(seed, 101), i, j);
    if (HashUnit(cell_seed, 0, 0) >= probability) return 0.0;
    const double radius =
        kMinRadius + (kMaxRadius - kMinRadius) * HashUnit(cell_seed, 1, 0);
    const Eigen::Vector2d centre(
        (i + 0.5) * kCell +
            (0.5 * kCell - radius) * (2 * HashUnit(cell_seed, 2, 0) - 1),
        (j + 0.5) * kCell +
            (0.5 * kCell - radius) * (2 * HashUnit(cell_seed, 3, 0) - 1));
    const double d = (p - centre).norm();
    return std::clamp((radius - d) / 0.05, 0.0, 1.0);
  }

  Eigen::Vector3f Colour(const Eigen::Vector2d& p) const {
    const RoadOptions& o = *options;
    const RouteCoordinates rc = ToRouteCoordinates(*route, p);
    const double from_centre = rc.left_m - o.lane_offset_m;
    const double half_width = 0.5 * o.road_width_m;
    if (std::abs(from_centre) <= half_width) {
      // Markings: 12 cm lines, dashed (3 m of 9 m) on the centre line, solid
      // 25 cm inside the edges.
      const double edge_line = half_width - 0.25;
      const bool centre_dash = std::abs(from_centre) < 0.06 &&
                               std::fmod(std::abs(rc.along_m), 9.0) < 3.0;
      const bool edge = std::abs(std::abs(from_centre) - edge_line) < 0.06;
      if (centre_dash || edge) return Eigen::Vector3f(0.85f, 0.85f, 0.82f);
      const double grain = PositionNoise(p, 0.04, 0.64, DeriveSeed(seed, 1));
      double value = 0.33 + o.road_contrast * grain;
      const double patch = PatchMask(p);
      if (patch > 0.0) {
        const double detail = PositionNoise(p, 0.04, 0.32, DeriveSeed(seed, 2));
        value += patch * (o.road_patch_contrast * detail - 0.05);
      }
      const float v = static_cast<float>(std::clamp(value, 0.0, 1.0));
      return Eigen::Vector3f(v, v, 1.03f * v);
    }
    const double n = PositionNoise(p, 0.10, 5.0, DeriveSeed(seed, 3));
    const double m = PositionNoise(p, 0.10, 1.6, DeriveSeed(seed, 4));
    const double shade = 1.0 + o.ground_contrast * 2.5 * n;
    return Eigen::Vector3f(
        static_cast<float>(std::clamp(0.36 * shade, 0.0, 1.0)),
        static_cast<float>(std::clamp(0.42 * shade + 0.04 * m, 0.0, 1.0)),
        static_cast<float>(std::clamp(0.24 * shade, 0.0, 1.0)));
  }
};

// A surface with the recipe of its texture: value noise of a size and seed,
// or a function of the surface point (a, b) in metres.
struct PendingSurface {
  Surface surface;
  uint64_t noise_seed = 0;
  int max_period_texels = 256;
  std::function<Eigen::Vector3f(double a, double b)> colour;  // or noise
};

Texture MakeTexture(const PendingSurface& pending) {
  const Surface& s = pending.surface;
  const int w =
      std::max(1, static_cast<int>(std::ceil(s.u_extent_m / s.texel_size_m)));
  const int h =
      std::max(1, static_cast<int>(std::ceil(s.v_extent_m / s.texel_size_m)));
  if (!pending.colour) {
    ValueNoiseOptions noise;
    noise.width = w;
    noise.height = h;
    noise.seed = pending.noise_seed;
    noise.max_period_texels = pending.max_period_texels;
    return MakeValueNoiseTexture(noise);
  }
  std::vector<float> rgb(static_cast<size_t>(w) * h * 3);
  for (int j = 0; j < h; ++j) {
    for (int i = 0; i < w; ++i) {
      const Eigen::Vector3f c = pending.colour((i + 0.5) * s.texel_size_m,
                                               (j + 0.5) * s.texel_size_m);
      for (int k = 0; k < 3; ++k)
        rgb[(static_cast<size_t>(j) * w + i) * 3 + k] = c[k];
    }
  }
  return Texture(w, h, std::move(rgb));
}

Surface VerticalRectangle(const Eigen::Vector2d& from,
                          const Eigen::Vector2d& to,
                          double bottom_z,
                          double height_m,
                          double texel_size_m) {
  const Eigen::Vector2d d = to - from;
  Surface s;
  s.origin = Eigen::Vector3d(from.x(), from.y(), bottom_z);
  s.u_axis = Eigen::Vector3d(d.x(), d.y(), 0.0).normalized();
  s.v_axis = Eigen::Vector3d::UnitZ();
  s.u_extent_m = d.norm();
  s.v_extent_m = height_m;
  s.texel_size_m = texel_size_m;
  return s;
}

}  // namespace

void RoadOptions::Check() const {
  Require(speed_mps > 0.0, "speed_mps must be > 0");
  Require(first_straight_m >= 0.0 && middle_straight_m >= 0.0 &&
              last_straight_m > 0.0,
          "straights must be >= 0 (the last > 0)");
  Require(turn_radius_m > road_width_m,
          "turn_radius_m must exceed road_width_m");
  Require(left_turn_deg >= 0.0 && left_turn_deg <= 180.0 &&
              right_turn_deg >= 0.0 && right_turn_deg <= 180.0,
          "turns must be within [0, 180] deg");
  Require(road_width_m > 0.0 && std::abs(lane_offset_m) < 0.5 * road_width_m,
          "road_width_m must be > 0 and |lane_offset_m| < half of it");
  Require(ground_cell_m > 0.0 && slope_wavelength_m > 0.0 && margin_m > 0.0,
          "ground_cell_m, slope_wavelength_m, margin_m must be > 0");
  Require(std::abs(slope_x_deg) < 20.0 && std::abs(slope_y_deg) < 20.0,
          "slope_x_deg and slope_y_deg must be within (-20, 20)");
  Require(far_wall_height_m > 0.0 && post_height_m > 0.0 &&
              post_spacing_m > 0.0 && post_setback_m >= 0.0,
          "far wall and post sizes must be > 0");
  Require(facade_min_setback_m >= 0.0 &&
              facade_max_setback_m >= facade_min_setback_m &&
              facade_length_m > 0.0 && facade_gap_m >= 0.0 &&
              facade_min_height_m > 0.0 &&
              facade_max_height_m >= facade_min_height_m,
          "facade sizes must be positive and min <= max");
  Require(road_texel_size_m > 0.0 && ground_texel_size_m > 0.0 &&
              structure_texel_size_m > 0.0 && far_texel_size_m > 0.0,
          "texel sizes must be > 0");
  Require(road_contrast >= 0.0 && road_patch_contrast >= 0.0 &&
              ground_contrast >= 0.0 && road_patch_fraction >= 0.0 &&
              road_patch_fraction <= 1.0,
          "contrasts must be >= 0 and road_patch_fraction in [0, 1]");
}

std::vector<RoutePiece> RoadRoute(const RoadOptions& options) {
  options.Check();
  const double k = 1.0 / options.turn_radius_m;
  const std::vector<std::pair<double, double>> pieces = {
      {options.first_straight_m, 0.0},
      {options.left_turn_deg * kDegToRad * options.turn_radius_m, k},
      {options.middle_straight_m, 0.0},
      {options.right_turn_deg * kDegToRad * options.turn_radius_m, -k},
      {options.last_straight_m, 0.0}};
  std::vector<RoutePiece> route;
  PlanarPose pose;
  for (const auto& [length, curvature] : pieces) {
    if (length <= 0.0) continue;
    route.push_back({pose, length, curvature});
    pose = UnicycleStep(pose, 1.0, curvature, length);
  }
  return route;
}

UnicyclePath MakeRoadPath(const RoadOptions& options, double duration_s) {
  const std::vector<RoutePiece> route = RoadRoute(options);
  double length = 0.0;
  std::vector<PathManoeuvre> manoeuvres;
  for (const RoutePiece& piece : route) {
    PathManoeuvre m;
    m.start_ns = SecondsToNs(length / options.speed_mps);
    length += piece.length_m;
    m.duration_ns = SecondsToNs(length / options.speed_mps) - m.start_ns;
    m.speed_mps = options.speed_mps;
    m.yaw_rate_radps = piece.curvature * options.speed_mps;
    m.start = piece.start;
    manoeuvres.push_back(m);
  }
  if (length / options.speed_mps < duration_s) {
    throw std::invalid_argument(
        "RoadOptions: the route is shorter than the drive (" +
        std::to_string(length / options.speed_mps) + " s < " +
        std::to_string(duration_s) + " s): lengthen last_straight_m");
  }
  return UnicyclePath(std::move(manoeuvres));
}

RoadGround::RoadGround(const Eigen::Vector2d& min_xy,
                       double cell_m,
                       std::vector<double> f_knots,
                       std::vector<double> g_knots)
    : min_xy_(min_xy),
      cell_m_(cell_m),
      f_(std::move(f_knots)),
      g_(std::move(g_knots)) {
  if (!(cell_m > 0.0) || f_.size() < 2 || g_.size() < 2) {
    throw std::invalid_argument("RoadGround: need cell_m > 0, >= 2 knots");
  }
}

Eigen::Vector2d RoadGround::max_xy() const {
  return min_xy_ + cell_m_ * Eigen::Vector2d(num_cells_x(), num_cells_y());
}

double RoadGround::F(double x, double* slope) const {
  const double u = (x - min_xy_.x()) / cell_m_;
  const int i =
      std::clamp(static_cast<int>(std::floor(u)), 0, num_cells_x() - 1);
  *slope = (f_[i + 1] - f_[i]) / cell_m_;
  return f_[i] + (u - i) * (f_[i + 1] - f_[i]);
}

double RoadGround::G(double y, double* slope) const {
  const double u = (y - min_xy_.y()) / cell_m_;
  const int i =
      std::clamp(static_cast<int>(std::floor(u)), 0, num_cells_y() - 1);
  *slope = (g_[i + 1] - g_[i]) / cell_m_;
  return g_[i] + (u - i) * (g_[i + 1] - g_[i]);
}

double RoadGround::Height(const Eigen::Vector2d& p) const {
  double sx, sy;
  return F(p.x(), &sx) + G(p.y(), &sy);
}

Eigen::Vector2d RoadGround::Gradient(const Eigen::Vector2d& p) const {
  Eigen::Vector2d slope;
  F(p.x(), &slope.x());
  G(p.y(), &slope.y());
  return slope;
}

RoadGround MakeRoadGround(const RoadOptions& options) {
  const std::vector<RoutePiece> route = RoadRoute(options);
  Eigen::Vector2d lo(0, 0), hi(0, 0);
  double total = 0.0;
  for (const RoutePiece& piece : route) total += piece.length_m;
  for (double s = 0.0; s <= total + 0.5; s += 0.5) {
    const PlanarPose pose = RoutePoseAt(route, std::min(s, total));
    lo = lo.cwiseMin(Eigen::Vector2d(pose.x, pose.y));
    hi = hi.cwiseMax(Eigen::Vector2d(pose.x, pose.y));
  }
  const double cell = options.ground_cell_m;
  const Eigen::Vector2d min_xy =
      ((lo.array() - options.margin_m) / cell).floor() * cell;
  const Eigen::Vector2d max_xy =
      ((hi.array() + options.margin_m) / cell).ceil() * cell;
  const double wave = 2.0 * M_PI / options.slope_wavelength_m;
  const double ax = std::tan(options.slope_x_deg * kDegToRad);
  const double ay = std::tan(options.slope_y_deg * kDegToRad);
  // Knot heights on the integrals of the slopes (see the header).
  std::vector<double> f, g;
  for (double x = min_xy.x(); x <= max_xy.x() + 0.5 * cell; x += cell) {
    f.push_back(-ax / wave * std::cos(wave * x));
  }
  for (double y = min_xy.y(); y <= max_xy.y() + 0.5 * cell; y += cell) {
    g.push_back(ay / wave * std::sin(wave * y));
  }
  return RoadGround(min_xy, cell, std::move(f), std::move(g));
}

Rigid3d PoseOnGround(const RoadGround& ground, const PlanarPose& pose) {
  const Eigen::Vector2d p(pose.x, pose.y);
  const Eigen::Vector2d slope = ground.Gradient(p);
  const Eigen::Vector3d z =
      Eigen::Vector3d(-slope.x(), -slope.y(), 1.0).normalized();
  // The car moves along its x axis (its wheels do not slip sideways): the
  // heading lifted onto the ground, the direction in which the path climbs.
  // It lies in the ground's plane, so it is normal to z.
  const double c = std::cos(pose.yaw_rad);
  const double s = std::sin(pose.yaw_rad);
  const Eigen::Vector3d x =
      Eigen::Vector3d(c, s, c * slope.x() + s * slope.y()).normalized();
  Eigen::Matrix3d rotation;
  rotation.col(0) = x;
  rotation.col(1) = z.cross(x);
  rotation.col(2) = z;
  return Rigid3d(Eigen::Quaterniond(rotation).normalized(),
                 Eigen::Vector3d(pose.x, pose.y, ground.Height(p)));
}

RoomScene BuildRoadScene(const RoadOptions& options,
                         const RoomSceneOptions& scene_options) {
  options.Check();
  scene_options.Check();
  const std::vector<RoutePiece> route = RoadRoute(options);
  const RoadGround ground = MakeRoadGround(options);
  std::vector<PendingSurface> pending;
  const uint64_t seed = scene_options.seed;
  const GroundLook look{&options, &route, DeriveSeed(seed, 1)};

  // Ground: one parallelogram per cell, at the road's texel size where the
  // road may pass.
  const double cell = ground.cell_m();
  const double road_reach =
      0.5 * options.road_width_m + std::abs(options.lane_offset_m) + cell;
  for (int i = 0; i < ground.num_cells_x(); ++i) {
    for (int j = 0; j < ground.num_cells_y(); ++j) {
      const Eigen::Vector2d corner =
          ground.min_xy() + cell * Eigen::Vector2d(i, j);
      const double z00 = ground.Height(corner);
      const Eigen::Vector3d u(
          cell, 0.0, ground.Height(corner + Eigen::Vector2d(cell, 0)) - z00);
      const Eigen::Vector3d v(
          0.0, cell, ground.Height(corner + Eigen::Vector2d(0, cell)) - z00);
      PendingSurface p;
      p.surface.origin = Eigen::Vector3d(corner.x(), corner.y(), z00);
      p.surface.u_axis = u.normalized();
      p.surface.v_axis = v.normalized();
      p.surface.u_extent_m = u.norm();
      p.surface.v_extent_m = v.norm();
      const Eigen::Vector2d centre =
          corner + 0.5 * cell * Eigen::Vector2d(1, 1);
      const bool near_road =
          std::abs(ToRouteCoordinates(route, centre).left_m) < road_reach;
      p.surface.texel_size_m =
          near_road ? options.road_texel_size_m : options.ground_texel_size_m;
      const double ux = cell / u.norm(), vy = cell / v.norm();
      p.colour = [look, corner, ux, vy](double a, double b) {
        return look.Colour(corner + Eigen::Vector2d(a * ux, b * vy));
      };
      pending.push_back(std::move(p));
    }
  }

  // Far walls on the ground's boundary, from below its lowest point.
  double lowest = std::numeric_limits<double>::infinity();
  for (int i = 0; i <= ground.num_cells_x(); ++i) {
    for (int j = 0; j <= ground.num_cells_y(); ++j) {
      lowest = std::min(
          lowest,
          ground.Height(ground.min_xy() + cell * Eigen::Vector2d(i, j)));
    }
  }
  const Eigen::Vector2d lo = ground.min_xy(), hi = ground.max_xy();
  const std::vector<Eigen::Vector2d> corners = {
      lo, Eigen::Vector2d(hi.x(), lo.y()), hi, Eigen::Vector2d(lo.x(), hi.y())};
  for (int k = 0; k < 4; ++k) {
    PendingSurface p;
    p.surface = VerticalRectangle(corners[k],
                                  corners[(k + 1) % 4],
                                  lowest - 1.0,
                                  options.far_wall_height_m + 1.0,
                                  options.far_texel_size_m);
    pending.push_back(std::move(p));
  }

  // Posts and facades along the route, both sides.
  std::mt19937_64 rng(DeriveSeed(seed, 2));
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  double total = 0.0;
  for (const RoutePiece& piece : route) total += piece.length_m;
  const auto offset_point = [&](double s, double left) {
    const PlanarPose pose = RoutePoseAt(route, s);
    return Eigen::Vector2d(pose.x - std::sin(pose.yaw_rad) * left,
                           pose.y + std::cos(pose.yaw_rad) * left);
  };
  const double half = 0.5 * options.road_width_m;
  // Road edges relative to the route: left at lane_offset + half, right at
  // lane_offset - half.
  const double edges[2] = {options.lane_offset_m + half,
                           options.lane_offset_m - half};
  for (int side = 0; side < 2; ++side) {
    const double sign = side == 0 ? 1.0 : -1.0;
    for (double s = options.post_spacing_m * (0.3 + 0.5 * side); s < total;
         s += options.post_spacing_m) {
      const Eigen::Vector2d c =
          offset_point(s, edges[side] + sign * options.post_setback_m);
      const double bottom = ground.Height(c) - 0.5;
      const double w = 0.25;
      const Eigen::Vector2d p00 = c + Eigen::Vector2d(-w / 2, -w / 2);
      const Eigen::Vector2d p10 = c + Eigen::Vector2d(w / 2, -w / 2);
      const Eigen::Vector2d p11 = c + Eigen::Vector2d(w / 2, w / 2);
      const Eigen::Vector2d p01 = c + Eigen::Vector2d(-w / 2, w / 2);
      const Eigen::Vector2d box[5] = {p00, p10, p11, p01, p00};
      for (int e = 0; e < 4; ++e) {
        PendingSurface p;
        p.surface = VerticalRectangle(box[e],
                                      box[e + 1],
                                      bottom,
                                      options.post_height_m + 0.5,
                                      options.structure_texel_size_m);
        p.max_period_texels = 16;
        pending.push_back(std::move(p));
      }
    }
    double s = options.facade_gap_m * unit(rng);
    while (s < total) {
      const double length = options.facade_length_m * (0.6 + 0.8 * unit(rng));
      const double setback =
          options.facade_min_setback_m +
          (options.facade_max_setback_m - options.facade_min_setback_m) *
              unit(rng);
      const double height =
          options.facade_min_height_m +
          (options.facade_max_height_m - options.facade_min_height_m) *
              unit(rng);
      const double end = std::min(total, s + length);
      // Chords of at most 4 m follow the turns.
      const int pieces =
          std::max(1, static_cast<int>(std::ceil((end - s) / 4.0)));
      for (int k = 0; k < pieces; ++k) {
        const double s0 = s + (end - s) * k / pieces;
        const double s1 = s + (end - s) * (k + 1) / pieces;
        const double left = edges[side] + sign * setback;
        const Eigen::Vector2d a = offset_point(s0, left);
        const Eigen::Vector2d b = offset_point(s1, left);
        if ((b - a).norm() < 0.05) continue;
        PendingSurface p;
        p.surface = VerticalRectangle(
            a,
            b,
            std::min(ground.Height(a), ground.Height(b)) - 0.5,
            height + 0.5,
            options.structure_texel_size_m);
        pending.push_back(std::move(p));
      }
      s = end + options.facade_gap_m * (0.5 + unit(rng));
    }
  }

  // Textures, on num_threads threads; noise seeds by surface index.
  RoomScene scene;
  std::vector<std::optional<Texture>> textures(pending.size());
  for (size_t i = 0; i < pending.size(); ++i) {
    pending[i].noise_seed = DeriveSeed(DeriveSeed(seed, 3), i);
    pending[i].surface.texture_index = static_cast<int>(i);
  }
  const auto work = [&](int thread) {
    for (size_t i = thread; i < pending.size();
         i += scene_options.num_threads) {
      textures[i] = MakeTexture(pending[i]);
    }
  };
  std::vector<std::thread> threads;
  for (int t = 1; t < scene_options.num_threads; ++t) {
    threads.emplace_back(work, t);
  }
  work(0);
  for (std::thread& thread : threads) thread.join();
  for (size_t i = 0; i < pending.size(); ++i) {
    scene.surfaces.push_back(pending[i].surface);
    scene.textures.push_back(std::move(*textures[i]));
  }
  return scene;
}

}  // namespace odomcal
