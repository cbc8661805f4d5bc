// sensor_msgs/CameraInfo -> the COLMAP camera odomcal uses as fixed
// intrinsics.
//
// Pixel centre convention: ROS (and OpenCV, which calibrates CameraInfo) put
// the centre of the top-left pixel at (0, 0); COLMAP puts it at (0.5, 0.5)
// (its SIFT adds 0.5 to VLFeat's integer-centred keypoints,
// src/colmap/feature/sift.cc, and its default principal point is width / 2).
// So the principal point moves by half a pixel:
//   cx_colmap = cx_ros + 0.5,  cy_colmap = cy_ros + 0.5;
// focal lengths and distortion coefficients are unchanged, as COLMAP's
// OPENCV, FULL_OPENCV and OPENCV_FISHEYE models apply OpenCV's formulas to
// the normalised coordinates (src/colmap/sensor/models.h).
//
// Distortion models (CameraInfo's D -> COLMAP's model and parameter order):
//   D empty or all zero (plumb_bob, rational_polynomial or no model)
//                                      -> PINHOLE (fx, fy, cx, cy)
//   plumb_bob (k1 k2 p1 p2 k3), k3 = 0 -> OPENCV (fx, fy, cx, cy, k1, k2, p1,
//                                         p2)
//   plumb_bob with k3 != 0, or
//   rational_polynomial (k1 k2 p1 p2 k3 k4 k5 k6)
//                                      -> FULL_OPENCV (fx, fy, cx, cy, k1, k2,
//                                         p1, p2, k3, k4, k5, k6)
//   equidistant (k1 k2 k3 k4)          -> OPENCV_FISHEYE (fx, fy, cx, cy, k1,
//                                         k2, k3, k4), also with D all zero
//                                         or empty: the ideal fisheye
//                                         r = f * theta is no pinhole
// The intrinsics are K's (the raw, distorted image's camera), not P's: the
// images are extracted unrectified.
//
// Refused with FormatError("<context>: <field>: <problem>"), where context
// names the bag and topic: an unknown distortion_model, a D whose length does
// not fit the model, a zero, negative or non-finite focal length in K, K with
// skew, binning other than 0 or 1, a width or height of 0, a region of
// interest (roi) that is not all zero or the full image, and
// (CheckCameraInfoImageSize) a CameraInfo whose size differs from the images'.
#pragma once

#include "odomcal/adapters/bag/ros_messages.h"
#include "odomcal/adapters/colmap_model.h"

#include <cstdint>
#include <string>

namespace odomcal::bag {

// The camera (camera_id 1) for `info`; see the top of this file.
ColmapCamera ColmapCameraFromCameraInfo(const CameraInfoMessage& info,
                                        const std::string& context);

// Throws FormatError when the images are not info.width x info.height.
void CheckCameraInfoImageSize(const CameraInfoMessage& info,
                              uint32_t image_width,
                              uint32_t image_height,
                              const std::string& context);

// One cameras.txt line: "CAMERA_ID MODEL WIDTH HEIGHT PARAMS..." with the
// parameters in the fewest digits (15 to 17) that read back exactly, no line
// break.
std::string ColmapCameraLine(const ColmapCamera& camera);

// The same camera as odomcal run's flags, e.g.
// "--camera_model OPENCV --camera_params 458.654,457.296,367.715,...".
std::string OdomcalCameraFlags(const ColmapCamera& camera);

}  // namespace odomcal::bag
