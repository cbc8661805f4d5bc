#include "odomcal/plugin/report/rig_report_html.h"

#include "odomcal/datasets/simulation/camera_mount.h"
#include "odomcal/solver/angles.h"
#include "odomcal/solver/format_number.h"

#include <gtest/gtest.h>

#include <cmath>
#include <regex>
#include <stdexcept>
#include <string>
#include <vector>

namespace odomcal {
namespace {

bool Has(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

size_t Count(const std::string& text, const std::string& part) {
  size_t count = 0;
  for (size_t at = text.find(part); at != std::string::npos;
       at = text.find(part, at + 1)) {
    ++count;
  }
  return count;
}

RigReportCamera Calibrated(const std::string& name, const Rigid3d& mount) {
  RigReportCamera camera;
  camera.name = name;
  camera.status = "success";
  camera.reason = "calibrated";
  camera.calibrated = true;
  CalibrationResult& r = camera.result;
  r.status = CalibrationStatus::kSuccess;
  r.has_estimate = true;
  r.odom_from_cam = mount;
  r.metric_scales = {0.37, 1.9};
  r.observability.metric_scales = {Determination::kEstimated,
                                   Determination::kEstimated};
  r.stddev_roll_pitch_yaw_deg = Eigen::Vector3d(0.01, 0.02, 0.03);
  r.stddev_translation_xy_m = Eigen::Vector2d(0.002, 0.003);
  r.stddev_metric_scales_rel = {0.001, 0.002};
  r.diagnostics.num_pairs_in = 120;
  r.diagnostics.num_pairs_used = 110;
  camera.clock_offset_s = 0.02;
  camera.clock_offset_estimated = true;
  camera.clock_offset_stddev_s = 0.001;
  camera.num_images = 400;
  camera.report_path = "cameras/" + name + "/report.html";
  return camera;
}

// front looks ahead-left, rear backwards (yaw 180), right's images did not
// fit the odometry; front and rear disagree on sub-model 1's scale.
RigReport ThreeCameraRig() {
  RigReport rig;
  rig.cameras.push_back(Calibrated(
      "front", MakeCameraMount(30.0, 10.0, 0.0, {0.30, 0.10, 0.50})));
  rig.cameras.push_back(Calibrated(
      "rear", MakeCameraMount(180.0, 15.0, 0.0, {-0.20, 0.05, 0.50})));
  RigReportCamera right;
  right.name = "right";
  right.status = "input_error";
  right.reason = "no image time inside the odometry's <span>";
  right.num_images = 12;
  rig.cameras.push_back(right);
  rig.reference = 1;
  RigReportPair pair;
  pair.camera_a = 0;
  pair.camera_b = 1;
  pair.transform.camb_from_cama = Inverse(rig.cameras[1].result.odom_from_cam) *
                                  rig.cameras[0].result.odom_from_cam;
  pair.transform.covariance = 1e-6 * Eigen::Matrix<double, 6, 6>::Identity();
  pair.transform.angle_deg =
      RotationAngle(pair.transform.camb_from_cama.rotation) * kRadToDeg;
  rig.pairs.push_back(pair);
  SharedSubModelScale agree{0, 1, "0", 0.37, 0.3702, 0.4};
  SharedSubModelScale disagree{0, 1, "1", 1.9, 1.98, 5.2};
  rig.shared_scales = {agree, disagree};
  return rig;
}

std::string Svg(const std::string& html) {
  const size_t begin = html.find("<svg");
  const size_t end = html.find("</svg>");
  return begin == std::string::npos || end == std::string::npos
             ? std::string()
             : html.substr(begin, end + 6 - begin);
}

TEST(RigReportHtml, NamesEveryCameraAndWhyOneWasNotCalibrated) {
  const std::string html = RigReportHtml(ThreeCameraRig());
  for (const char* name :
       {"front",
        "rear<br><span style=\"white-space:nowrap\">(reference)</span>",
        "right"}) {
    EXPECT_TRUE(Has(html, std::string("</span> ") + name + "</td>")) << name;
  }
  EXPECT_TRUE(Has(html,
                  "right</td><td style=\"white-space:nowrap\">"
                  "input_error</td>"));
  EXPECT_TRUE(Has(html,
                  "<td colspan=\"6\" class=\"reason\">not calibrated: no "
                  "image time inside the odometry's &lt;span&gt;</td>"));
  EXPECT_TRUE(Has(html, "<a href=\"cameras/front/report.html\">open</a>"));
  EXPECT_TRUE(Has(html, "<td>none</td></tr>"));  // right has no report
  EXPECT_TRUE(Has(html, "2 of 3 cameras calibrated"));
  // front's yaw and x with their 3-sigma bounds, its scales and pairs.
  const Eigen::Vector3d rpy =
      RollPitchYaw(ThreeCameraRig().cameras[0].result.odom_from_cam.rotation) *
      kRadToDeg;
  EXPECT_TRUE(
      Has(html, "yaw " + FormatPrintf("%.3f", rpy.z()) + " &plusmn; 0.090"));
  EXPECT_TRUE(Has(html, "x 30.00 &plusmn; 0.60"));
  EXPECT_TRUE(Has(html, "z 50.00 (held)"));
  EXPECT_TRUE(Has(html, "20.00 &plusmn; 3.00"));  // clock offset, ms
  EXPECT_TRUE(Has(html, "0.37000 &plusmn; 0.30 %<br>1.90000"));
  EXPECT_TRUE(Has(html, ">110 of 120</td>"));
}

TEST(RigReportHtml, EveryRowHasAllColumns) {
  const std::string html = RigReportHtml(ThreeCameraRig());
  const std::regex row("<tr[^>]*>(.*?)</tr>");
  const std::regex cell("<t[dh]( colspan=\"([0-9]+)\")?[^>]*>");
  std::vector<int> widths;
  for (std::sregex_iterator it(html.begin(), html.end(), row), end; it != end;
       ++it) {
    const std::string cells = (*it)[1];
    int width = 0;
    for (std::sregex_iterator c(cells.begin(), cells.end(), cell); c != end;
         ++c) {
      width += (*c)[2].matched ? std::stoi((*c)[2]) : 1;
    }
    widths.push_back(width);
  }
  // Cameras: header and three rows; pairs: header and one; scales: header
  // and two.
  EXPECT_EQ(widths, (std::vector<int>{9, 9, 9, 9, 6, 6, 8, 8, 8}));
}

TEST(RigReportHtml, DrawsAPyramidPerCalibratedCameraWithFiniteNumbers) {
  const RigReport rig = ThreeCameraRig();
  const std::string svg = Svg(RigReportHtml(rig));
  ASSERT_FALSE(svg.empty());
  // Two views, each: two axis arrows and a pyramid per calibrated camera.
  EXPECT_EQ(Count(svg, "<path d="), 2u * (2u + 2u));
  EXPECT_EQ(Count(svg, ">front</text>"), 3u);  // the legend and two labels
  EXPECT_EQ(Count(svg, ">rear</text>"), 3u);
  EXPECT_FALSE(Has(svg, ">right</text>"));
  for (const char* axis : {">x</text>", ">y</text>", ">z</text>"}) {
    EXPECT_TRUE(Has(svg, axis)) << axis;
  }
  EXPECT_TRUE(Has(svg, "odometry origin (base frame)"));
  // Every number of every attribute is finite.
  const std::regex attribute("=\"([^\"]*)\"");
  const std::regex number("[-+]?[0-9]*\\.?[0-9]+([eE][-+]?[0-9]+)?");
  int num_numbers = 0;
  for (std::sregex_iterator it(svg.begin(), svg.end(), attribute), end;
       it != end;
       ++it) {
    const std::string value = (*it)[1];
    EXPECT_EQ(value.find("nan"), std::string::npos) << value;
    EXPECT_EQ(value.find("inf"), std::string::npos) << value;
    for (std::sregex_iterator n(value.begin(), value.end(), number); n != end;
         ++n) {
      EXPECT_TRUE(std::isfinite(std::stod(n->str()))) << value;
      ++num_numbers;
    }
  }
  EXPECT_GT(num_numbers, 100);
}

// A camera with yaw 180 looks backwards: its pyramid's base lies behind its
// centre, in the geometry and in the top view's pixels.
TEST(RigReportHtml, ACameraTurnedAroundPointsBackwards) {
  const RigReport rig = ThreeCameraRig();
  const Rigid3d& rear = rig.cameras[1].result.odom_from_cam;
  const std::vector<Eigen::Vector3d> pyramid = CameraPyramid(rear, 0.2);
  ASSERT_EQ(pyramid.size(), 5u);
  EXPECT_NEAR((pyramid[0] - rear.translation).norm(), 0.0, 1e-12);
  const Eigen::Vector3d base_centre =
      0.25 * (pyramid[1] + pyramid[2] + pyramid[3] + pyramid[4]);
  EXPECT_LT(base_centre.x(), pyramid[0].x() - 0.15);
  // Image top-left is to the camera's left: for a camera looking backwards,
  // towards the robot's right (-y).
  EXPECT_LT(pyramid[1].y(), pyramid[2].y());
  // The top view's pyramid of rear (its colour, the first of its two
  // paths): corners 1, 2, 3, 4, 1, then the apex.
  const std::string svg = Svg(RigReportHtml(rig));
  const std::regex path(
      "<path d=\"([^\"]*)\" fill=\"none\" stroke=\"#8c564b\"");
  std::smatch match;
  ASSERT_TRUE(std::regex_search(svg, match, path));
  const std::string d = match[1];
  std::vector<double> numbers;
  const std::regex number("-?[0-9.]+");
  for (std::sregex_iterator n(d.begin(), d.end(), number), end; n != end; ++n) {
    numbers.push_back(std::stod(n->str()));
  }
  ASSERT_GE(numbers.size(), 12u);
  const double corner_x_px = numbers[0], apex_x_px = numbers[10];
  EXPECT_LT(corner_x_px, apex_x_px - 20.0);
}

TEST(RigReportHtml, DisagreeingScalesAreHighlighted) {
  const std::string html = RigReportHtml(ThreeCameraRig());
  EXPECT_EQ(Count(html, "class=\"disagree\""), 1u);
  EXPECT_TRUE(Has(html, "<td>1</td><td>1.90000</td><td>1.98000</td>"));
  EXPECT_TRUE(Has(html, "<strong style=\"color:#b02020\">disagree</strong>"));
  EXPECT_TRUE(Has(html, "<td>+0.4</td><td>agree</td>"));
}

TEST(RigReportHtml, WithoutPairsOrSharedScalesSaysSo) {
  RigReport rig = ThreeCameraRig();
  rig.cameras.resize(1);
  rig.reference = 0;
  rig.pairs.clear();
  rig.shared_scales.clear();
  const std::string html = RigReportHtml(rig);
  EXPECT_TRUE(Has(html, "no transform between cameras"));
  EXPECT_TRUE(Has(html, "no scale to compare"));
  rig.reference = 3;
  EXPECT_THROW(RigReportHtml(rig), std::invalid_argument);
}

TEST(RigReportHtml, NoCameraCalibratedStillDrawsTheOrigin) {
  RigReport rig = ThreeCameraRig();
  for (RigReportCamera& camera : rig.cameras) camera.calibrated = false;
  rig.pairs.clear();
  const std::string svg = Svg(RigReportHtml(rig));
  EXPECT_EQ(Count(svg, "<path d="), 4u);  // the axes alone
  EXPECT_FALSE(Has(svg, "nan"));
}

}  // namespace
}  // namespace odomcal
