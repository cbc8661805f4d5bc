// The physical cameras of a COLMAP project: which registered images belong
// to which camera of the robot, so that each camera is calibrated against the
// odometry from its own images (a rig's cameras share the robot's motion, not
// their poses: mixing them in one trajectory makes every pair between two
// cameras a jump that no odometry explains).
//
// COLMAP stores one camera per set of intrinsics (cameras.bin, camera_id).
// A rig's images usually sit in one sub-folder per camera (COLMAP's
// ImageReader.single_camera_per_folder; "front/000001.png"), and COLMAP 3.12+
// rigs give every sensor its own camera_id. How the images are grouped:
//   1. Every image name has a sub-folder and every camera_id's images lie in
//      one sub-folder: one camera per sub-folder, named by it (also when
//      COLMAP gave every image a camera of its own within the folders).
//   2. Else, when COLMAP gave most images a camera of their own (more
//      camera_ids than half the images): one camera of all images, as a
//      single-camera project.
//   3. Else one camera per camera_id, named "camera_<id>".
// Names are made of A-Z a-z 0-9 _ - . ('/' and other characters become '_'),
// since they become frame names.
#pragma once

#include <cstdint>
#include <set>
#include <string>
#include <vector>

namespace odomcal {

enum class ColmapCameraGrouping {
  kSingleCamera,  // one camera_id
  kBySubFolder,   // rule 1
  kOnePerImage,   // rule 2: treated as one camera
  kByCameraId,    // rule 3
};

struct ColmapProjectCamera {
  std::string name;
  std::set<uint32_t> camera_ids;  // COLMAP's, in the project's models
  int num_images = 0;  // registered in any sub-model, each image once
};

struct ColmapProjectCameras {
  ColmapCameraGrouping grouping = ColmapCameraGrouping::kSingleCamera;
  // In order of name (sub-folders) or camera_id.
  std::vector<ColmapProjectCamera> cameras;

  bool IsRig() const { return cameras.size() > 1; }
};

// How the registered images of the models under `sparse_path` (the folders
// of FindColmapModelFolders) group into cameras. Throws FormatError as
// ReadColmapModel does.
ColmapProjectCameras FindColmapProjectCameras(const std::string& sparse_path);

// The grouping of images given as (camera_id, name), one per registered
// image (an image in several sub-models counted once): the rules above.
struct ColmapImageCamera {
  uint32_t camera_id = 0;
  std::string name;
};
ColmapProjectCameras GroupColmapImagesIntoCameras(
    const std::vector<ColmapImageCamera>& images);

// A camera name (A-Z a-z 0-9 _ - ., at most 100 characters) from a folder
// or topic: other characters become '_'.
std::string CameraNameFromText(const std::string& text);

// "by sub-folder", ... for messages.
const char* ColmapCameraGroupingText(ColmapCameraGrouping grouping);

}  // namespace odomcal
