#include "odomcal/adapters/colmap_cameras.h"

#include "odomcal/adapters/colmap_model.h"
#include "odomcal/adapters/colmap_segments.h"

#include <map>
#include <utility>

namespace odomcal {
namespace {

// The sub-folder of an image name ("front/a/1.png" -> "front/a"), or "".
std::string SubFolder(const std::string& name) {
  const size_t slash = name.rfind('/');
  return slash == std::string::npos ? std::string() : name.substr(0, slash);
}

}  // namespace

std::string CameraNameFromText(const std::string& text) {
  std::string name;
  for (const char c : text) {
    const bool allowed = (c >= 'A' && c <= 'Z') || (c >= 'a' && c <= 'z') ||
                         (c >= '0' && c <= '9') || c == '_' || c == '-' ||
                         c == '.';
    name += allowed ? c : '_';
  }
  return name.substr(0, 100);
}

const char* ColmapCameraGroupingText(ColmapCameraGrouping grouping) {
  switch (grouping) {
    case ColmapCameraGrouping::kSingleCamera:
      return "one camera";
    case ColmapCameraGrouping::kBySubFolder:
      return "one camera per image sub-folder";
    case ColmapCameraGrouping::kOnePerImage:
      return "one camera (COLMAP gave most images intrinsics of their own)";
    case ColmapCameraGrouping::kByCameraId:
      return "one camera per COLMAP camera_id";
  }
  return "";
}

ColmapProjectCameras GroupColmapImagesIntoCameras(
    const std::vector<ColmapImageCamera>& images) {
  std::map<std::string, uint32_t> camera_of_image;
  for (const ColmapImageCamera& image : images) {
    camera_of_image.emplace(image.name, image.camera_id);
  }
  std::map<uint32_t, std::set<std::string>> folders_of_camera;
  std::map<std::string, std::set<uint32_t>> cameras_of_folder;
  std::map<std::string, int> images_of_folder;
  std::map<uint32_t, int> images_of_camera;
  bool every_image_in_a_folder = true;
  for (const auto& [name, camera_id] : camera_of_image) {
    const std::string folder = SubFolder(name);
    every_image_in_a_folder = every_image_in_a_folder && !folder.empty();
    folders_of_camera[camera_id].insert(folder);
    cameras_of_folder[folder].insert(camera_id);
    ++images_of_folder[folder];
    ++images_of_camera[camera_id];
  }
  bool one_folder_per_camera = true;
  for (const auto& [camera_id, folders] : folders_of_camera) {
    one_folder_per_camera = one_folder_per_camera && folders.size() == 1;
  }

  ColmapProjectCameras out;
  const auto all_in_one = [&](ColmapCameraGrouping grouping) {
    out.grouping = grouping;
    ColmapProjectCamera camera;
    camera.name = "camera";
    for (const auto& [camera_id, count] : images_of_camera) {
      camera.camera_ids.insert(camera_id);
      camera.num_images += count;
    }
    if (camera.num_images > 0) out.cameras.push_back(camera);
    return out;
  };
  if (every_image_in_a_folder && one_folder_per_camera &&
      cameras_of_folder.size() > 1) {
    out.grouping = ColmapCameraGrouping::kBySubFolder;
    std::set<std::string> names;
    for (const auto& [folder, camera_ids] : cameras_of_folder) {
      ColmapProjectCamera camera;
      camera.name = CameraNameFromText(folder);
      // Two folders that differ only in characters a frame name cannot hold.
      for (int k = 2; !names.insert(camera.name).second; ++k) {
        camera.name =
            CameraNameFromText(folder).substr(0, 90) + "_" + std::to_string(k);
      }
      camera.camera_ids = camera_ids;
      camera.num_images = images_of_folder.at(folder);
      out.cameras.push_back(camera);
    }
    return out;
  }
  if (images_of_camera.size() <= 1) {
    return all_in_one(ColmapCameraGrouping::kSingleCamera);
  }
  if (2 * images_of_camera.size() > camera_of_image.size()) {
    return all_in_one(ColmapCameraGrouping::kOnePerImage);
  }
  out.grouping = ColmapCameraGrouping::kByCameraId;
  for (const auto& [camera_id, count] : images_of_camera) {
    ColmapProjectCamera camera;
    camera.name = "camera_" + std::to_string(camera_id);
    camera.camera_ids = {camera_id};
    camera.num_images = count;
    out.cameras.push_back(camera);
  }
  return out;
}

ColmapProjectCameras FindColmapProjectCameras(const std::string& sparse_path) {
  std::vector<ColmapImageCamera> images;
  ColmapReadOptions options;
  options.read_points3D = false;
  for (const std::string& folder : FindColmapModelFolders(sparse_path)) {
    const ColmapModel model = ReadColmapModel(folder, options);
    for (const auto& [id, image] : model.images) {
      images.push_back({image.camera_id, image.name});
    }
  }
  return GroupColmapImagesIntoCameras(images);
}

}  // namespace odomcal
