// COLMAP sparse models (cameras, images, points3D, and from COLMAP 3.12 on
// rigs and frames) in COLMAP's binary and text formats, read and written as
// COLMAP 3.8 to 4.1 do (3.8's src/base/reconstruction.cc; cameras, images
// and points3D are unchanged up to 4.1, rigs and frames come with 3.12:
// src/colmap/scene/reconstruction_io_{binary,text}.cc).
//
// Poses: an image stores cam_from_world, the map from the model's world
// frame ("sfm" in odomcal's vocabulary) into the camera frame
// (x right, y down, z forward):  p_in_cam = cam_from_world * p_in_world.
// Files store it as QW QX QY QZ TX TY TZ (Hamilton quaternion, scalar first).
// The camera centre is Inverse(cam_from_world).translation, and the relative
// motion of two images is
//   cam_i_from_cam_j = cam_i_from_world * Inverse(cam_j_from_world).
//
// Binary layout (little endian; counts are uint64):
//   cameras.bin   count, then per camera: uint32 camera_id, int32 model_id,
//                 uint64 width, uint64 height, float64
//                 params[num_params(model)]
//   images.bin    count, then per image: uint32 image_id, float64 qw qx qy qz,
//                 float64 tx ty tz, uint32 camera_id, name bytes + '\0',
//                 uint64 num_points2D, per point float64 x, y, uint64
//                 point3D_id (2^64 - 1 = none)
//   points3D.bin  count, then per point: uint64 point3D_id, float64 x y z,
//                 uint8 r g b, float64 error, uint64 track_length, per element
//                 uint32 image_id, uint32 point2D_idx
// Text layout: '#' comment lines, then one line per camera
// ("CAMERA_ID MODEL_NAME WIDTH HEIGHT PARAMS..."), TWO lines per image
// ("IMAGE_ID QW QX QY QZ TX TY TZ CAMERA_ID NAME", then "X Y POINT3D_ID ..."
// with -1 for none; the second line may be empty) and one line per point
// ("POINT3D_ID X Y Z R G B ERROR IMAGE_ID POINT2D_IDX ...").
//
// Rigs and frames (rigs.bin/frames.bin, or .txt beside a text model; their
// layout is in colmap_model_rigs_binary.cc / _text.cc): COLMAP >= 3.12 takes
// each image's pose from the frame that lists it, rig_from_world for the
// rig's reference camera and sensor_from_rig * rig_from_world for another
// camera, and ignores the pose in images.bin. ReadColmapModel does the same,
// so ColmapImage::cam_from_world is the pose COLMAP uses. A model with only
// one of the two files, an image in no frame, or a camera without
// sensor_from_rig is refused, as COLMAP cannot read it either. Without both
// files the images' own poses are used (COLMAP 3.8-3.11, and 3.12+ builds
// trivial rigs and frames from them).
//
// Reading is strict, and throws FormatError naming the file and, for text,
// "path:line", for binary "path: byte N" plus the record, on: truncated
// files, trailing bytes, unknown camera models, parameter counts that do not
// match the model, non-finite numbers, quaternions whose norm is not within
// 1e-2 of 1 (they are then normalised, as COLMAP does), duplicate ids, wrong
// column counts, ids out of range, images naming a camera the model does not
// have, and tracks naming a missing image or point2D index. Every count in a
// binary file is checked against the bytes that remain BEFORE anything is
// allocated, so a garbled count fails fast instead of allocating gigabytes.
#pragma once

#include "odomcal/solver/rigid3.h"

#include <Eigen/Core>

#include <array>
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace odomcal {

// COLMAP's camera models with their COLMAP ids (the value) and parameter
// counts (ColmapCameraModelNumParams), in COLMAP's parameter order. Ids 0-10
// exist in every COLMAP from 3.8 on; the others from the release named:
//   0 SIMPLE_PINHOLE 3 (f, cx, cy)        1 PINHOLE 4 (fx, fy, cx, cy)
//   2 SIMPLE_RADIAL 4 (f, cx, cy, k)      3 RADIAL 5 (f, cx, cy, k1, k2)
//   4 OPENCV 8 (fx, fy, cx, cy, k1, k2, p1, p2)
//   5 OPENCV_FISHEYE 8 (fx, fy, cx, cy, k1, k2, k3, k4)
//   6 FULL_OPENCV 12 (fx, fy, cx, cy, k1, k2, p1, p2, k3, k4, k5, k6)
//   7 FOV 5 (fx, fy, cx, cy, omega)       8 SIMPLE_RADIAL_FISHEYE 4 (f, cx, cy,
//   k) 9 RADIAL_FISHEYE 5 (f, cx, cy, k1, k2) 10 THIN_PRISM_FISHEYE 12 (fx, fy,
//   cx, cy, k1, k2, p1, p2, k3, k4, sx1, sy1) 11 RAD_TAN_THIN_PRISM_FISHEYE 16
//   (fx, fy, cx, cy, k0, k1, k2, k3, k4, k5,
//      p0, p1, s0, s1, s2, s3)                                    COLMAP 3.11
//   12 SIMPLE_DIVISION 4 (f, cx, cy, k)   13 DIVISION 5 (fx, fy, cx, cy, k)
//   14 SIMPLE_FISHEYE 3 (f, cx, cy)       15 FISHEYE 4 (fx, fy, cx, cy)
//                                                                 COLMAP 4.0
//   16 EUCM 6 (fx, fy, cx, cy, alpha, beta)
//   17 EQUIRECTANGULAR 2 (w, h: the panorama's size; no focal length)
//                                                                 COLMAP 4.1
// (COLMAP's src/colmap/sensor/models.h, InitializeParamsInfo, at the tags.)
enum class ColmapCameraModel : int {
  kSimplePinhole = 0,
  kPinhole = 1,
  kSimpleRadial = 2,
  kRadial = 3,
  kOpenCV = 4,
  kOpenCVFisheye = 5,
  kFullOpenCV = 6,
  kFov = 7,
  kSimpleRadialFisheye = 8,
  kRadialFisheye = 9,
  kThinPrismFisheye = 10,
  kRadTanThinPrismFisheye = 11,
  kSimpleDivision = 12,
  kDivision = 13,
  kSimpleFisheye = 14,
  kFisheye = 15,
  kEucm = 16,
  kEquirectangular = 17,
};

// COLMAP's name, e.g. "SIMPLE_RADIAL". Throws std::invalid_argument for a
// value outside the enum.
const char* ColmapCameraModelName(ColmapCameraModel model);
// Number of intrinsic parameters. Throws std::invalid_argument like above.
int ColmapCameraModelNumParams(ColmapCameraModel model);
// The model with this COLMAP id or name; std::nullopt when unknown.
std::optional<ColmapCameraModel> ColmapCameraModelFromId(int model_id);
std::optional<ColmapCameraModel> ColmapCameraModelFromName(
    std::string_view name);

// Where a model keeps its pinhole part: params[fx], params[fy] (the same
// index for the one-focal models), params[cx], params[cy].
struct ColmapPinholeIndices {
  int fx = 0;
  int fy = 0;
  int cx = 0;
  int cy = 0;
};
// std::nullopt for EQUIRECTANGULAR, which has no focal length (its view is
// the full sphere). Throws std::invalid_argument like above.
std::optional<ColmapPinholeIndices> ColmapCameraModelPinholeIndices(
    ColmapCameraModel model);

struct ColmapCamera {
  uint32_t camera_id = 0;
  ColmapCameraModel model = ColmapCameraModel::kSimplePinhole;
  uint64_t width = 0;   // pixels
  uint64_t height = 0;  // pixels
  // ColmapCameraModelNumParams(model) values, in COLMAP's order (see above).
  std::vector<double> params;
};

// point3D_id of a 2D point without a 3D point ("-1" in text, 2^64 - 1 in
// binary files).
constexpr int64_t kColmapNoPoint3D = -1;

struct ColmapPoint2D {
  Eigen::Vector2d xy = Eigen::Vector2d::Zero();  // pixels, COLMAP's convention
  int64_t point3D_id = kColmapNoPoint3D;         // >= 0, or kColmapNoPoint3D
};

struct ColmapImage {
  uint32_t image_id = 0;
  // Path relative to the image folder, '/'-separated, e.g. "cam0/000123.png".
  // Non-empty; no '\0'; for text files also no blanks or line breaks (COLMAP's
  // text reader would split the name there).
  std::string name;
  uint32_t camera_id = 0;
  Rigid3d cam_from_world;  // unit quaternion (see the top of this file)
  std::vector<ColmapPoint2D> points2D;
};

struct ColmapTrackElement {
  uint32_t image_id = 0;
  uint32_t point2D_idx = 0;  // index into that image's points2D
};

struct ColmapPoint3D {
  int64_t point3D_id = 0;                         // >= 0
  Eigen::Vector3d xyz = Eigen::Vector3d::Zero();  // world frame
  std::array<uint8_t, 3> rgb = {0, 0, 0};
  double error = -1.0;  // mean reprojection error, pixels (-1: not computed)
  std::vector<ColmapTrackElement> track;
};

// One reconstruction. Map keys equal the ids stored in the values.
struct ColmapModel {
  std::map<uint32_t, ColmapCamera> cameras;
  std::map<uint32_t, ColmapImage> images;  // registered images only
  std::map<int64_t, ColmapPoint3D> points3D;
};

enum class ColmapFormat { kBinary, kText };

// The format of the model in `dir`, decided as COLMAP's Reconstruction::Read
// does: kBinary when cameras.bin, images.bin and points3D.bin all exist
// (even if the .txt files exist too: BINARY IS PREFERRED), else kText when
// cameras.txt, images.txt and points3D.txt all exist, else std::nullopt.
std::optional<ColmapFormat> DetectColmapModelFormat(const std::string& dir);

struct ColmapReadOptions {
  // False skips points3D.bin / points3D.txt (which must still exist), for
  // callers that only need poses; ColmapModel::points3D is then empty and the
  // points2D -> point3D references are not cross-checked.
  bool read_points3D = true;
};

// Reads the model in `dir` in the format DetectColmapModelFormat picks.
// Throws FormatError naming `dir` when neither complete set of files exists,
// and naming the file (see the top of this file) when one is malformed.
ColmapModel ReadColmapModel(const std::string& dir,
                            const ColmapReadOptions& options = {});

// Writes cameras, images, points3D, rigs and frames to `dir` (created if
// missing) in `format`, records in increasing id order, byte for byte as
// COLMAP writes them: binary little endian; text with COLMAP's headers and
// numbers in "%.17g" form (locale-independent), quaternions normalised.
// Rigs and frames are the trivial ones COLMAP >= 3.12 builds for a model
// without them: one rig per camera (rig_id = camera_id, the camera its only
// sensor) and one frame per image (frame_id = image_id, rig_id = camera_id,
// rig_from_world = the image's cam_from_world, the same numbers as in
// images.bin). They are written rather than left out because a folder may
// hold rigs/frames of an earlier model: COLMAP >= 3.12 would take the poses
// from those stale frames. Writing them makes every folder odomcal writes
// consistent whatever was there, and the same model COLMAP >= 3.12 would
// build itself (a camera that was a non-reference sensor of a rig becomes a
// rig of its own, its images keeping their composed poses); COLMAP 3.8-3.11
// ignore the two files. Existing files of that format are replaced (rigs and
// frames are removed first); files of the other format are left alone, so
// writing text into a folder that holds .bin files leaves a folder that
// readers (COLMAP and ReadColmapModel) still read as the OLD binary model.
// Throws std::invalid_argument when the model cannot be written faithfully
// (map key differing from the id, parameter count not matching the model,
// non-finite values, a zero quaternion, an unrepresentable name, a point3D_id
// below -1), naming the record; FormatError naming the file on I/O errors.
void WriteColmapModel(const ColmapModel& model,
                      const std::string& dir,
                      ColmapFormat format);

}  // namespace odomcal
