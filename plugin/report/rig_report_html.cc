// The rig section in four parts: the camera table (numbers with 3-sigma
// bounds from each camera's covariance, the reason for a camera that was
// not calibrated), the camera-to-camera table (rotation angle and distance
// with first-order 3-sigma bounds from the pair's covariance), the
// shared-scale table (disagreements beyond 3 sigma highlighted) and the
// figure: every calibrated camera as a pyramid from its optical centre
// along its optical axis, projected onto the odometry's x-y plane (top
// view) and x-z plane (side view), drawn with svg_plot at equal scales.

#include "odomcal/plugin/report/rig_report_html.h"

#include "odomcal/plugin/report/svg_plot.h"
#include "odomcal/solver/angles.h"
#include "odomcal/solver/format_number.h"

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>
#include <stdexcept>
#include <utility>

namespace odomcal {
namespace {

// Half the pyramid's base over its depth: a wide 4:3 view, only a sketch
// of the viewing direction.
constexpr double kPyramidHalfWidth = 0.7;
constexpr double kPyramidHalfHeight = 0.5;

// Colours unlike the axes' red, green and blue (the top view's palette of
// colmap_report.cc).
const char* RigCameraColor(size_t index) {
  static const char* const kColors[] = {
      "#9467bd", "#8c564b", "#e377c2", "#17becf", "#bcbd22", "#7f7f7f"};
  return kColors[index % 6];
}

// A cell of numbers with their bounds: a line break only between numbers.
constexpr const char* kRigNumberCell = "<td style=\"white-space:nowrap\">";

// "1.234 &plusmn; 0.056" (3 sigma), or the value alone without a sigma.
std::string RigValueHtml(const char* format,
                         double value,
                         std::optional<double> three_sigma) {
  std::string text = FormatPrintf(format, value);
  if (three_sigma) text += " &plusmn; " + FormatPrintf(format, *three_sigma);
  return text;
}

bool RigZEstimated(const CalibrationResult& result) {
  return result.observability.translation_z == Determination::kEstimated ||
         result.translation_z_prior.moved_by_data;
}

std::string RigCameraRowHtml(const RigReportCamera& camera,
                             bool reference,
                             size_t index) {
  std::ostringstream row;
  row << "<tr><td><span style=\"color:" << RigCameraColor(index)
      << "\">&#9632;</span> " << EscapeMarkup(camera.name)
      << (reference
              ? "<br><span style=\"white-space:nowrap\">(reference)</span>"
              : "")
      << "</td>" << kRigNumberCell << EscapeMarkup(camera.status) << "</td>";
  const std::string link = camera.report_path.empty()
                               ? std::string("none")
                               : "<a href=\"" +
                                     EscapeMarkup(camera.report_path) + "\">" +
                                     "open</a>";
  if (!camera.calibrated) {
    row << "<td colspan=\"6\" class=\"reason\">not calibrated: "
        << EscapeMarkup(camera.reason) << "</td><td>" << link << "</td></tr>\n";
    return row.str();
  }
  const CalibrationResult& r = camera.result;
  const Eigen::Vector3d rpy =
      RollPitchYaw(r.odom_from_cam.rotation) * kRadToDeg;
  const char* angle_names[3] = {"roll", "pitch", "yaw"};
  row << kRigNumberCell;
  for (int k = 0; k < 3; ++k) {
    row << (k > 0 ? "<br>" : "") << angle_names[k] << " "
        << RigValueHtml("%.3f", rpy(k), 3.0 * r.stddev_roll_pitch_yaw_deg(k));
  }
  const Eigen::Vector3d t = 100.0 * r.odom_from_cam.translation;
  row << "</td>" << kRigNumberCell << "x "
      << RigValueHtml("%.2f", t.x(), 300.0 * r.stddev_translation_xy_m.x())
      << "<br>y "
      << RigValueHtml("%.2f", t.y(), 300.0 * r.stddev_translation_xy_m.y())
      << "<br>z "
      << (RigZEstimated(r)
              ? RigValueHtml("%.2f", t.z(), 300.0 * r.stddev_translation_z_m)
              : FormatPrintf("%.2f", t.z()) + " (held)")
      << "</td>" << kRigNumberCell;
  if (!camera.clock_offset_s) {
    row << "not estimated";
  } else if (camera.clock_offset_estimated) {
    row << RigValueHtml("%.2f",
                        1000.0 * *camera.clock_offset_s,
                        3000.0 * camera.clock_offset_stddev_s);
  } else {
    row << FormatPrintf("%.2f", 1000.0 * *camera.clock_offset_s) << " (held)";
  }
  row << "</td>" << kRigNumberCell;
  for (size_t k = 0; k < r.metric_scales.size(); ++k) {
    row << (k > 0 ? "<br>" : "");
    if (!r.observability.ScaleDetermined(k)) {
      row << "undetermined";
      continue;
    }
    row << FormatPrintf("%.5f", r.metric_scales[k]);
    if (k < r.stddev_metric_scales_rel.size()) {
      row << " &plusmn; "
          << FormatPrintf("%.2f", 300.0 * r.stddev_metric_scales_rel[k])
          << " %";
    }
  }
  if (r.metric_scales.empty()) row << "none";
  row << "</td><td>" << camera.num_images << "</td>" << kRigNumberCell
      << r.diagnostics.num_pairs_used << " of " << r.diagnostics.num_pairs_in
      << "</td><td>" << link << "</td></tr>\n";
  return row.str();
}

// First-order sigma of |v| for v with covariance `covariance`: the variance
// along v's direction (the largest one's root when v is about zero).
double RigNormSigma(const Eigen::Vector3d& v,
                    const Eigen::Matrix3d& covariance) {
  const double norm = v.norm();
  if (norm < 1e-9) {
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver(
        covariance, Eigen::EigenvaluesOnly);
    return std::sqrt(std::max(0.0, solver.eigenvalues().maxCoeff()));
  }
  const Eigen::Vector3d u = v / norm;
  return std::sqrt(std::max(0.0, u.dot(covariance * u)));
}

std::string RigPairRowHtml(const RigReport& rig, const RigReportPair& pair) {
  const CameraPairTransform& t = pair.transform;
  const Eigen::Vector3d rpy =
      RollPitchYaw(t.camb_from_cama.rotation) * kRadToDeg;
  const Eigen::Vector3d translation = 100.0 * t.camb_from_cama.translation;
  // d|log R| / d psi = u^T for a left perturbation Exp(psi) R (u the axis).
  const double angle_sigma_deg =
      RigNormSigma(LogRotation(t.camb_from_cama.rotation),
                   t.covariance.topLeftCorner<3, 3>()) *
      kRadToDeg;
  const double distance_sigma_cm =
      100.0 * RigNormSigma(t.camb_from_cama.translation,
                           t.covariance.bottomRightCorner<3, 3>());
  std::ostringstream row;
  row << "<tr><td>" << EscapeMarkup(rig.cameras[pair.camera_b].name) << "_from_"
      << EscapeMarkup(rig.cameras[pair.camera_a].name) << "</td>"
      << kRigNumberCell
      << RigValueHtml("%.3f", t.angle_deg, 3.0 * angle_sigma_deg) << "</td>"
      << kRigNumberCell;
  // Roll, pitch and yaw without their sigmas, which grow without bound near
  // pitch +-90 deg (a side camera against a rear one): the rotation's 3
  // sigma about camB's axes instead.
  const char* angle_names[3] = {"roll", "pitch", "yaw"};
  for (int k = 0; k < 3; ++k) {
    char value[32];
    std::snprintf(value, sizeof(value), "%.3f", rpy(k));
    row << (k > 0 ? "<br>" : "") << angle_names[k] << " " << value;
  }
  char axes[96];
  std::snprintf(axes,
                sizeof(axes),
                "<br>3&sigma; about x, y, z: %.3f, %.3f, %.3f",
                3.0 * t.stddev_rotation_axes_deg.x(),
                3.0 * t.stddev_rotation_axes_deg.y(),
                3.0 * t.stddev_rotation_axes_deg.z());
  row << axes << "</td>" << kRigNumberCell;
  const char axis_names[3] = {'x', 'y', 'z'};
  for (int k = 0; k < 3; ++k) {
    row << (k > 0 ? "<br>" : "") << axis_names[k] << " "
        << RigValueHtml(
               "%.2f", translation(k), 300.0 * t.stddev_translation_m(k));
  }
  row << "</td>" << kRigNumberCell
      << RigValueHtml("%.2f", translation.norm(), 3.0 * distance_sigma_cm)
      << "</td><td>" << (t.odom_offset_z_held ? "held" : "estimated")
      << "</td></tr>\n";
  return row.str();
}

std::string RigSharedScaleRowHtml(const RigReport& rig,
                                  const SharedSubModelScale& scale) {
  const bool disagree = scale.Disagrees();
  std::ostringstream row;
  row << "<tr"
      << (disagree ? " class=\"disagree\" style=\"background:#fde2df\"" : "")
      << "><td>" << EscapeMarkup(rig.cameras[scale.camera_a].name)
      << "</td><td>" << EscapeMarkup(rig.cameras[scale.camera_b].name)
      << "</td><td>" << EscapeMarkup(scale.sub_model) << "</td><td>"
      << FormatPrintf("%.5f", scale.scale_a) << "</td><td>"
      << FormatPrintf("%.5f", scale.scale_b) << "</td><td>"
      << FormatPrintf("%+.2f", 100.0 * (scale.scale_b / scale.scale_a - 1.0))
      << "</td><td>"
      << (std::isfinite(scale.sigmas) ? FormatPrintf("%+.1f", scale.sigmas)
                                      : std::string("no sigma"))
      << "</td><td>"
      << (disagree ? "<strong style=\"color:#b02020\">disagree</strong>"
                   : "agree")
      << "</td></tr>\n";
  return row.str();
}

// A line from `from` to `to` with an arrow head, as one series (breaks at
// NaN).
void RigAddArrow(const Eigen::Vector2d& from,
                 const Eigen::Vector2d& to,
                 PlotSeries* series) {
  const double nan = std::nan("");
  const Eigen::Vector2d d = to - from;
  const Eigen::Vector2d side(-d.y(), d.x());
  const Eigen::Vector2d left = to - 0.18 * d + 0.09 * side;
  const Eigen::Vector2d right = to - 0.18 * d - 0.09 * side;
  for (const Eigen::Vector2d& p : {from, to, left}) {
    series->x.push_back(p.x());
    series->y.push_back(p.y());
  }
  series->x.push_back(nan);
  series->y.push_back(nan);
  for (const Eigen::Vector2d& p : {to, right}) {
    series->x.push_back(p.x());
    series->y.push_back(p.y());
  }
  series->x.push_back(nan);
  series->y.push_back(nan);
}

// The section's figure: panel 0 the top view (x, y), panel 1 the side view
// (x, z).
PlotFigure RigFigure(const RigReport& rig,
                     double* pyramid_depth_m,
                     double* axis_length_m) {
  // Sizes from the rig's extent, so that a rig of any size reads alike.
  double extent = 0.0;
  for (const RigReportCamera& camera : rig.cameras) {
    if (camera.calibrated) {
      extent = std::max(extent, camera.result.odom_from_cam.translation.norm());
    }
  }
  extent = std::max(extent, 0.05);
  *pyramid_depth_m = 0.3 * extent;
  *axis_length_m = 0.4 * extent;
  const double nan = std::nan("");

  PlotFigure figure;
  figure.title = "Cameras on the robot";
  figure.num_columns = 2;
  figure.panel_width_px = 480.0;
  figure.panel_height_px = 440.0;
  figure.legend_title = "Drawn:";
  const int axes[2][2] = {{0, 1}, {0, 2}};  // x, y and x, z
  const char* titles[2] = {"from above", "from the right side"};
  const char* y_labels[2] = {"y [m] (left)", "z [m] (up)"};
  const char* axis_names[3] = {"x", "y", "z"};
  const char* axis_colors[3] = {"#d62728", "#2ca02c", "#1f77b4"};
  const char* axis_labels[3] = {
      "odometry x (forward)", "odometry y (left)", "odometry z (up)"};
  for (int view = 0; view < 2; ++view) {
    const int h = axes[view][0], v = axes[view][1];
    PlotPanel& panel = figure.panels.emplace_back();
    panel.title = titles[view];
    panel.x_label = "x [m] (forward)";
    panel.y_label = y_labels[view];
    panel.equal_aspect = true;
    for (int axis = 0; axis < 3; ++axis) {
      PlotSeries arrow;
      arrow.label = axis_labels[axis];
      arrow.color = axis_colors[axis];
      arrow.markers = false;
      // The axis along the view is not drawn; its empty series keeps the
      // legend in the order x, y, z.
      if (axis != h && axis != v) {
        panel.series.push_back(arrow);
        continue;
      }
      const Eigen::Vector2d tip(axis == h ? *axis_length_m : 0.0,
                                axis == v ? *axis_length_m : 0.0);
      RigAddArrow(Eigen::Vector2d::Zero(), tip, &arrow);
      panel.series.push_back(arrow);
      PlotLabel label;
      label.x = tip.x();
      label.y = tip.y();
      label.text = axis_names[axis];
      label.color = axis_colors[axis];
      label.bold = true;
      label.dx_px = axis == h ? 6.0 : -4.0;
      label.dy_px = axis == h ? 4.0 : -6.0;
      panel.labels.push_back(label);
    }
    PlotSeries origin{"odometry origin (base frame)", {0.0}, {0.0}, "#000000"};
    origin.line = false;
    origin.marker_shape = MarkerShape::kSquare;
    origin.marker_radius_px = 4.0;
    panel.series.push_back(origin);
    for (size_t k = 0; k < rig.cameras.size(); ++k) {
      const RigReportCamera& camera = rig.cameras[k];
      if (!camera.calibrated) continue;
      const Rigid3d& odom_from_cam = camera.result.odom_from_cam;
      const std::vector<Eigen::Vector3d> p =
          CameraPyramid(odom_from_cam, *pyramid_depth_m);
      PlotSeries pyramid;
      pyramid.label = camera.name;
      pyramid.color = RigCameraColor(k);
      pyramid.markers = false;
      // Every edge once: the base, then apex to each corner.
      for (const int corner : {1, 2, 3, 4, 1, 0, 2, -1, 3, 0, 4}) {
        pyramid.x.push_back(corner < 0 ? nan : p[corner](h));
        pyramid.y.push_back(corner < 0 ? nan : p[corner](v));
      }
      panel.series.push_back(pyramid);
      PlotSeries centre{camera.name, {p[0](h)}, {p[0](v)}, RigCameraColor(k)};
      centre.line = false;
      centre.marker_radius_px = 3.5;
      panel.series.push_back(centre);
      // The name behind the camera, away from its pyramid; beside it when
      // the view looks along the optical axis.
      const Eigen::Vector3d forward =
          odom_from_cam.rotation.toRotationMatrix().col(2);
      Eigen::Vector2d away(-forward(h), -forward(v));
      PlotLabel label;
      label.x = p[0](h);
      label.y = p[0](v);
      label.text = camera.name;
      label.color = RigCameraColor(k);
      label.bold = true;
      if (away.norm() < 0.3) {
        // Above the pyramid, which surrounds the centre in this view.
        double top = p[0](v);
        for (const Eigen::Vector3d& corner : p) top = std::max(top, corner(v));
        label.y = top;
        label.anchor = PlotLabel::Anchor::kMiddle;
        label.dy_px = -6.0;
      } else {
        away.normalize();
        label.anchor = away.x() > 0.3    ? PlotLabel::Anchor::kStart
                       : away.x() < -0.3 ? PlotLabel::Anchor::kEnd
                                         : PlotLabel::Anchor::kMiddle;
        label.dx_px = 10.0 * away.x();
        // Pixels grow downwards; +4 centres the text on the direction.
        label.dy_px = -14.0 * away.y() + 4.0;
      }
      panel.labels.push_back(label);
    }
  }
  return figure;
}

}  // namespace

std::vector<Eigen::Vector3d> CameraPyramid(const Rigid3d& odom_from_cam,
                                           double depth_m) {
  std::vector<Eigen::Vector3d> points = {Eigen::Vector3d::Zero()};
  const double w = kPyramidHalfWidth, h = kPyramidHalfHeight;
  for (const auto& [x, y] : {std::pair(-w, -h),
                             std::pair(w, -h),
                             std::pair(w, h),
                             std::pair(-w, h)}) {
    points.push_back(depth_m * Eigen::Vector3d(x, y, 1.0));
  }
  for (Eigen::Vector3d& point : points) point = odom_from_cam * point;
  return points;
}

std::string RigReportHtml(const RigReport& rig) {
  const int num_cameras = static_cast<int>(rig.cameras.size());
  auto check = [&](int index) {
    if (index < 0 || index >= num_cameras) {
      throw std::invalid_argument("RigReportHtml: camera index " +
                                  std::to_string(index) + " out of range");
    }
  };
  check(rig.reference);
  for (const RigReportPair& pair : rig.pairs) {
    check(pair.camera_a);
    check(pair.camera_b);
  }
  for (const SharedSubModelScale& scale : rig.shared_scales) {
    check(scale.camera_a);
    check(scale.camera_b);
  }
  int num_calibrated = 0;
  for (const RigReportCamera& camera : rig.cameras) {
    num_calibrated += camera.calibrated;
  }

  std::ostringstream html;
  html << "<section id=\"rig\">\n<h2>Cameras of the rig</h2>\n<p>"
       << num_calibrated << " of " << num_cameras
       << " cameras calibrated, each from its own images against the one "
          "odometry. The estimate above is the reference camera's ("
       << EscapeMarkup(rig.cameras[rig.reference].name)
       << "); each camera's own report has its plots.";
  if (!rig.adjusted_together.empty()) {
    std::string names;
    for (const std::string& name : rig.adjusted_together) {
      names += (names.empty() ? "" : ", ") + EscapeMarkup(name);
    }
    html << " Then adjusted together with the odometry (the rig's joint "
            "adjustment, "
         << EscapeMarkup(rig.joint_note) << "): " << names
         << ". Their rotation, x and y below are its; each camera's own "
            "report keeps its own calibration.";
    if (rig.num_points_across_cameras > 0) {
      html << " " << rig.num_points_across_cameras
           << " points of the reconstruction are seen by several cameras' "
              "images: one point each, which ties those cameras together "
              "directly.";
    }
  } else if (!rig.joint_note.empty()) {
    html << " " << EscapeMarkup(rig.joint_note);
  }
  html << "</p>\n";
  html << "<table class=\"rig-cameras\"><tr><th>camera</th><th>status</th>"
          "<th>roll, pitch, yaw [deg]</th><th>x, y, z [cm]</th>"
          "<th>clock offset [ms]</th><th>metric scale [m/unit]</th>"
          "<th>images</th><th>pairs used</th><th>own report</th></tr>\n";
  for (size_t k = 0; k < rig.cameras.size(); ++k) {
    html << RigCameraRowHtml(
        rig.cameras[k], static_cast<int>(k) == rig.reference, k);
  }
  html << "</table>\n<p>Rotation and translation of odom_from_cam "
          "(x_in_odom = odom_from_cam * x_in_cam) with 3-sigma bounds from "
          "the camera's covariance. z is held at --fixed_translation_z_m "
          "where the drive does not determine it (held). Clock offset: "
          "odometry time = camera time + offset. Metric scale: metres per "
          "COLMAP unit, one per segment of the camera's images, &plusmn; 3 "
          "sigma in percent. Images: the camera's registered images; pairs "
          "used: the motion pairs its calibration kept of those it "
          "formed.</p>\n";

  html << "<h3>Camera to camera</h3>\n";
  if (rig.pairs.empty()) {
    html << "<p>Fewer than two cameras calibrated: no transform between "
            "cameras.</p>\n";
  } else {
    html << "<table class=\"rig-pairs\"><tr><th>camB_from_camA</th>"
            "<th>rotation angle [deg]</th><th>roll, pitch, yaw [deg]</th>"
            "<th>translation [cm]</th><th>distance [cm]</th>"
            "<th>heights</th></tr>\n";
    for (const RigReportPair& pair : rig.pairs) {
      html << RigPairRowHtml(rig, pair);
    }
    html << "</table>\n<p>camB_from_camA = inverse(odom_from_camB) * "
            "odom_from_camA maps camera A's coordinates to camera B's. "
            "Rotation angle: the angle between the two cameras' "
            "orientations; translation: camera A's optical centre in camera "
            "B's frame (x right, y down, z forward), distance its length. "
         << (std::any_of(rig.pairs.begin(),
                         rig.pairs.end(),
                         [](const RigReportPair& pair) {
                           return pair.adjusted_together;
                         })
                 ? "3-sigma bounds from the rig's joint adjustment of the "
                   "cameras together, with their cross terms (the "
                   "trajectory's errors common to both cancel); "
                 : "3-sigma bounds from the two cameras' covariances as "
                   "independent estimates (their shared odometry's errors "
                   "are not in them); ")
         << "heights held: the translation follows from the two held z "
            "values along the odometry's z axis, not from a "
            "measurement.</p>\n";
  }

  html << "<h3>Shared metric scales</h3>\n";
  if (rig.shared_scales.empty()) {
    html << "<p>No sub-model holds two calibrated cameras' images as one "
            "segment each: no scale to compare.</p>\n";
  } else {
    html << "<table class=\"rig-scales\"><tr><th>camera A</th><th>camera "
            "B</th><th>sub-model</th><th>scale A [m/unit]</th><th>scale B "
            "[m/unit]</th><th>B / A &minus; 1 [%]</th><th>difference "
            "[sigma]</th><th>verdict</th></tr>\n";
    for (const SharedSubModelScale& scale : rig.shared_scales) {
      html << RigSharedScaleRowHtml(rig, scale);
    }
    html << "</table>\n<p>One COLMAP sub-model has one scale, so two cameras "
            "whose images it holds must find the same metric scale for it. "
            "Difference: (B / A &minus; 1) over its standard deviation (the "
            "two relative sigmas in quadrature); beyond 3 sigma the cameras "
            "disagree (red row) and cannot both be right.</p>\n";
  }

  double depth_m = 0.0, axis_m = 0.0;
  const PlotFigure figure = RigFigure(rig, &depth_m, &axis_m);
  html << "<figure>\n"
       << RenderSvg(figure)
       << "<figcaption>The calibrated cameras on the robot, in metres at "
          "equal scales on both axes of each view. Left: seen from above, x "
          "forward (right), y to the robot's left (up). Right: seen from "
          "the robot's right side, x forward (right), z up. Black square: "
          "the odometry origin (the base frame); red, green, blue arrows: "
          "its x, y and z axes, "
       << EscapeMarkup(FormatRounded(axis_m, 2))
       << " m long. Each camera calibrated: a dot at its optical centre "
          "(the translation of odom_from_cam) and a pyramid towards where it "
          "looks, its base "
       << EscapeMarkup(FormatRounded(depth_m, 2))
       << " m along the optical axis (camera z) and wider along image x "
          "than image y; a sketch of the viewing direction, not of the "
          "lens's field of view. A camera whose z is held is drawn at the "
          "held height. Cameras not calibrated are not drawn."
          "</figcaption>\n</figure>\n</section>\n";
  return html.str();
}

}  // namespace odomcal
