// COLMAP sparse output -> camera trajectories, one per reconstruction
// ("segment"), ready for AssociateCameraWithOdometry.
//
// The mapper writes its reconstructions to numbered sub-folders of its output
// folder (sparse/0, sparse/1, ...), each in its own similarity frame: own
// origin, orientation and scale. So every sub-model is one segment with its
// own metric scale. An image registered in several sub-models (they may share
// a few) appears in each of those segments, with that sub-model's pose;
// images the mapper did not register are simply absent.
//
// Per segment, pose k is the camera of image image_names[k]:
//   world_from_cam = Inverse(cam_from_world)   (world = that sub-model's frame)
// so that cam_i_from_cam_j = Inverse(world_from_cam_i) * world_from_cam_j =
// cam_i_from_world * Inverse(cam_j_from_world). Stamps come from an
// ImageTimestamps lookup by image NAME (never by image_id: ids follow import
// order, not name or time order, and differ between projects), and poses are
// sorted by stamp.
#pragma once

#include "odomcal/adapters/image_timestamps.h"
#include "odomcal/adapters/trajectory.h"

#include <cstdint>
#include <set>
#include <string>
#include <vector>

namespace odomcal {

struct ColmapSegment {
  // The model folder read, e.g. "project/sparse/1".
  std::string model_path;
  // Its name under the root ("0", "1", ...), or "" when the path given to
  // ReadColmapSegments was itself a model folder.
  std::string sub_model;
  // world_from_cam in the sub-model's frame (reconstruction units), strictly
  // increasing stamp_ns; planar = false; source = model_path.
  Trajectory trajectory;
  // image_names[k] and image_ids[k] (the id within this sub-model) belong to
  // trajectory.poses[k].
  std::vector<std::string> image_names;
  std::vector<uint32_t> image_ids;
  // Images registered in the sub-model, with or without a timestamp.
  int num_registered_images = 0;
  // Registered images left out because they have no timestamp (only with
  // ColmapSegmentOptions::skip_images_without_timestamp), and their names.
  int num_skipped_without_timestamp = 0;
  std::vector<std::string> skipped_image_names;
};

struct ColmapSegmentOptions {
  // false (default): a registered image without a timestamp is an error, since
  // it usually means the wrong timestamp file or unit. true: such images are
  // left out and counted in the segment.
  bool skip_images_without_timestamp = false;
  // Only the images of these COLMAP cameras (empty: every image): one camera
  // of a rig (colmap_cameras.h). A sub-model without any of its images then
  // gives no segment, and the counts are of its images only.
  std::set<uint32_t> camera_ids;
};

// The model folders under `sparse_path`:
//   - {sparse_path} itself when it holds a model (cameras, images, points3D
//     as .bin or .txt; see DetectColmapModelFormat), numbered sub-folders
//     then being ignored;
//   - else its sub-folders named by digits only, in numeric order ("2" before
//     "10"); other sub-folders are ignored.
// Throws FormatError naming the path when it is not a directory, when it
// holds neither a model nor numbered sub-folders, and naming the sub-folder
// when a numbered one holds no model.
std::vector<std::string> FindColmapModelFolders(const std::string& sparse_path);

// One segment per folder of FindColmapModelFolders(sparse_path), in that
// order (but for the folders without an image of options.camera_ids). points3D
// are not read. Throws FormatError as FindColmapModelFolders and
// ReadColmapModel do, and, naming the model folder and the image(s): when an
// image has no timestamp (unless skipped, see the options), and when two images
// of one sub-model have the same timestamp.
std::vector<ColmapSegment> ReadColmapSegments(
    const std::string& sparse_path,
    const ImageTimestamps& timestamps,
    const ColmapSegmentOptions& options = {});

// A sub-model that holds no image a larger sub-model does not also hold.
// COLMAP 3.8's mapper can reconstruct part of a scene a second time, in a
// frame of its own and sometimes folded. Measured on the rendered `small`
// preset, seed 1: sub-model 0 held images 26-37, all also in sub-model 1
// (images 1-37), folded; calibrating both counted those odometry motions
// twice, and the folded copy's pairs made a clean model look contradicted.
struct DuplicateSegment {
  ColmapSegment segment;
  std::string duplicate_of;  // sub_model of the segment holding its images
};

// Moves out of `segments` every non-empty segment whose image names are all
// in one segment with more images (of equal ones, the later is moved out),
// keeping the order of the others.
std::vector<DuplicateSegment> RemoveDuplicateSegments(
    std::vector<ColmapSegment>* segments);

}  // namespace odomcal
