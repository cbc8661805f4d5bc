// Finds the model folders (the path itself, or its numbered sub-folders),
// reads each model without points3D, looks every registered image's name up
// in the timestamps, inverts cam_from_world into world_from_cam, and sorts
// the poses by stamp; equal stamps in one segment are refused because a
// Trajectory needs strictly increasing stamps and the association could not
// tell the two images apart.
#include "odomcal/adapters/colmap_segments.h"

#include "odomcal/adapters/colmap_model.h"
#include "odomcal/adapters/format_error.h"
#include "odomcal/solver/rigid3.h"

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <numeric>
#include <set>
#include <system_error>
#include <utility>

namespace odomcal {
namespace {

namespace fs = std::filesystem;

bool IsNumberedName(const std::string& name) {
  return !name.empty() && std::all_of(name.begin(), name.end(), [](char c) {
    return std::isdigit(static_cast<unsigned char>(c)) != 0;
  });
}

// Numeric order on digit strings of any length: "2" < "10", "02" after "2".
bool NumericLess(const std::string& a, const std::string& b) {
  const size_t a_start = std::min(a.find_first_not_of('0'), a.size());
  const size_t b_start = std::min(b.find_first_not_of('0'), b.size());
  const size_t a_digits = a.size() - a_start;
  const size_t b_digits = b.size() - b_start;
  if (a_digits != b_digits) return a_digits < b_digits;
  const int order = a.compare(a_start, a_digits, b, b_start, b_digits);
  return order != 0 ? order < 0 : a < b;
}

struct StampedColmapImage {
  int64_t stamp_ns = 0;
  const ColmapImage* image = nullptr;
};

ColmapSegment MakeSegment(const std::string& model_path,
                          const std::string& sub_model,
                          const ImageTimestamps& timestamps,
                          const ColmapSegmentOptions& options) {
  ColmapReadOptions read_options;
  read_options.read_points3D = false;
  const ColmapModel model = ReadColmapModel(model_path, read_options);

  ColmapSegment segment;
  segment.model_path = model_path;
  segment.sub_model = sub_model;
  segment.trajectory.source = model_path;

  std::vector<StampedColmapImage> timed;
  timed.reserve(model.images.size());
  for (const auto& [id, image] : model.images) {
    if (!options.camera_ids.empty() &&
        options.camera_ids.count(image.camera_id) == 0) {
      continue;
    }
    ++segment.num_registered_images;
    std::string why;
    const std::optional<int64_t> stamp_ns = timestamps.Lookup(image.name, &why);
    if (!stamp_ns) {
      if (!options.skip_images_without_timestamp) {
        throw FormatError(model_path + ": registered image '" + image.name +
                          "' has no timestamp: " + why);
      }
      ++segment.num_skipped_without_timestamp;
      segment.skipped_image_names.push_back(image.name);
      continue;
    }
    timed.push_back({*stamp_ns, &image});
  }
  // Ties broken by name so that the error below is deterministic.
  std::sort(timed.begin(), timed.end(), [](const auto& a, const auto& b) {
    return a.stamp_ns != b.stamp_ns ? a.stamp_ns < b.stamp_ns
                                    : a.image->name < b.image->name;
  });
  for (size_t k = 0; k < timed.size(); ++k) {
    if (k > 0 && timed[k].stamp_ns == timed[k - 1].stamp_ns) {
      throw FormatError(model_path + ": images '" + timed[k - 1].image->name +
                        "' and '" + timed[k].image->name +
                        "' have the same timestamp (" +
                        std::to_string(timed[k].stamp_ns) + " ns, from " +
                        timestamps.source() + ")");
    }
    StampedPose pose;
    pose.stamp_ns = timed[k].stamp_ns;
    pose.world_from_sensor = Inverse(timed[k].image->cam_from_world);
    segment.trajectory.poses.push_back(pose);
    segment.image_names.push_back(timed[k].image->name);
    segment.image_ids.push_back(timed[k].image->image_id);
  }
  return segment;
}

}  // namespace

std::vector<std::string> FindColmapModelFolders(
    const std::string& sparse_path) {
  std::error_code error;
  if (!fs::is_directory(sparse_path, error)) {
    throw FormatError(sparse_path +
                      ": not a COLMAP sparse folder: no such directory");
  }
  if (DetectColmapModelFormat(sparse_path)) return {sparse_path};

  std::vector<std::string> names;
  for (fs::directory_iterator it(sparse_path, error), end; !error && it != end;
       it.increment(error)) {
    const std::string name = it->path().filename().string();
    if (IsNumberedName(name) && it->is_directory(error)) names.push_back(name);
  }
  if (error) {
    throw FormatError(sparse_path +
                      ": cannot list the directory: " + error.message());
  }
  if (names.empty()) {
    throw FormatError(sparse_path +
                      ": not a COLMAP sparse folder: neither a model "
                      "(cameras, images, points3D as .bin or .txt) nor "
                      "numbered sub-models (0, 1, ...)");
  }
  std::sort(names.begin(), names.end(), NumericLess);
  std::vector<std::string> folders;
  for (const std::string& name : names) {
    const std::string folder = (fs::path(sparse_path) / name).string();
    if (!DetectColmapModelFormat(folder)) {
      throw FormatError(folder +
                        ": numbered sub-folder without a COLMAP model "
                        "(cameras, images, points3D as .bin or .txt)");
    }
    folders.push_back(folder);
  }
  return folders;
}

std::vector<ColmapSegment> ReadColmapSegments(
    const std::string& sparse_path,
    const ImageTimestamps& timestamps,
    const ColmapSegmentOptions& options) {
  const std::vector<std::string> folders = FindColmapModelFolders(sparse_path);
  const bool single = folders.size() == 1 && folders.front() == sparse_path;
  std::vector<ColmapSegment> segments;
  for (const std::string& folder : folders) {
    const std::string sub_model =
        single ? std::string() : fs::path(folder).filename().string();
    ColmapSegment segment = MakeSegment(folder, sub_model, timestamps, options);
    if (options.camera_ids.empty() || segment.num_registered_images > 0) {
      segments.push_back(std::move(segment));
    }
  }
  return segments;
}

std::vector<DuplicateSegment> RemoveDuplicateSegments(
    std::vector<ColmapSegment>* segments) {
  std::vector<std::set<std::string>> names;
  for (const ColmapSegment& segment : *segments) {
    names.emplace_back(segment.image_names.begin(), segment.image_names.end());
  }
  // holder[k]: the segment that holds every image of segment k, or -1.
  std::vector<int> holder(segments->size(), -1);
  for (size_t k = 0; k < segments->size(); ++k) {
    if (names[k].empty()) continue;
    for (size_t other = 0; other < segments->size() && holder[k] < 0; ++other) {
      const bool larger = names[other].size() > names[k].size() ||
                          (names[other].size() == names[k].size() && other < k);
      if (other != k && larger &&
          std::includes(names[other].begin(),
                        names[other].end(),
                        names[k].begin(),
                        names[k].end())) {
        holder[k] = static_cast<int>(other);
      }
    }
  }
  std::vector<std::string> sub_models;
  for (const ColmapSegment& segment : *segments)
    sub_models.push_back(segment.sub_model);
  std::vector<DuplicateSegment> duplicates;
  std::vector<ColmapSegment> kept;
  for (size_t k = 0; k < segments->size(); ++k) {
    if (holder[k] < 0) {
      kept.push_back(std::move((*segments)[k]));
      continue;
    }
    // A holder that is a duplicate itself: its own holder has the images too.
    int root = holder[k];
    while (holder[root] >= 0) root = holder[root];
    duplicates.push_back({std::move((*segments)[k]), sub_models[root]});
  }
  *segments = std::move(kept);
  return duplicates;
}

}  // namespace odomcal
