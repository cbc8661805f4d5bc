// What rigs and frames mean for the images of a model (COLMAP >= 3.12):
// COLMAP attaches each image to the frame that lists it and computes the
// image's cam_from_world from the frame (src/colmap/scene/image.h,
// Image::CamFromWorld -> Frame::SensorFromWorld); the pose stored in
// images.bin / images.txt is read and discarded. The trivial rigs and frames
// are those COLMAP builds for a model that has none
// (reconstruction_io_utils.cc: CreateOneRigPerCamera, CreateFrameForImage).
#include "odomcal/adapters/colmap_model_internal.h"
#include "odomcal/adapters/format_error.h"

#include <limits>
#include <map>
#include <string>
#include <utility>

namespace odomcal::internal {

RigMap TrivialRigs(const ColmapModel& model) {
  RigMap rigs;
  for (const auto& [camera_id, camera] : model.cameras) {
    Rig rig;
    rig.rig_id = camera_id;
    rig.ref_sensor = SensorId{kSensorCamera, camera_id};
    rigs.emplace(camera_id, std::move(rig));
  }
  return rigs;
}

FrameMap TrivialFrames(const ColmapModel& model) {
  FrameMap frames;
  for (const auto& [image_id, image] : model.images) {
    Frame frame;
    frame.frame_id = image_id;
    frame.rig_id = image.camera_id;
    frame.rig_from_world =
        Rigid3d(NormalizedRotation(image), image.cam_from_world.translation);
    frame.data.push_back(
        FrameData{SensorId{kSensorCamera, image.camera_id}, image_id});
    frames.emplace(image_id, std::move(frame));
  }
  return frames;
}

void PoseImagesFromFrames(const RigMap& rigs,
                          const FrameMap& frames,
                          std::map<uint32_t, ColmapImage>* images,
                          const std::string& rigs_path,
                          const std::string& frames_path) {
  // image_id -> the frame listing it as a camera's data.
  std::map<uint32_t, const Frame*> frame_of_image;
  for (const auto& [frame_id, frame] : frames) {
    const std::string label = "frame_id " + std::to_string(frame_id);
    if (rigs.count(frame.rig_id) == 0) {
      throw FormatError(frames_path + ": " + label + " names rig_id " +
                        std::to_string(frame.rig_id) + ", which is not in " +
                        rigs_path);
    }
    for (const FrameData& data : frame.data) {
      // Other sensors' data, and images COLMAP did not register, have no
      // entry in images.bin; COLMAP ignores them here too.
      if (data.sensor.type != kSensorCamera ||
          data.data_id > std::numeric_limits<uint32_t>::max() ||
          images->count(static_cast<uint32_t>(data.data_id)) == 0) {
        continue;
      }
      const uint32_t image_id = static_cast<uint32_t>(data.data_id);
      const ColmapImage& image = images->at(image_id);
      if (data.sensor.id != image.camera_id) {
        throw FormatError(frames_path + ": " + label + " lists " +
                          ImageLabel(image) + " as data of camera " +
                          std::to_string(data.sensor.id) +
                          ", but the image's camera_id is " +
                          std::to_string(image.camera_id));
      }
      if (!frame_of_image.emplace(image_id, &frame).second) {
        throw FormatError(frames_path + ": " + ImageLabel(image) +
                          " is in two frames (" +
                          std::to_string(frame_of_image[image_id]->frame_id) +
                          " and " + std::to_string(frame_id) + ")");
      }
    }
  }
  for (auto& [image_id, image] : *images) {
    const auto found = frame_of_image.find(image_id);
    if (found == frame_of_image.end()) {
      throw FormatError(frames_path + ": " + ImageLabel(image) +
                        " is in no frame (COLMAP >= 3.12 takes each image's "
                        "pose from its frame and cannot read this model)");
    }
    const Frame& frame = *found->second;
    const Rig& rig = rigs.at(frame.rig_id);
    const std::string where =
        rigs_path + ": rig_id " + std::to_string(rig.rig_id) + " (frame_id " +
        std::to_string(frame.frame_id) + " of " + ImageLabel(image) + ")";
    if (rig.ref_sensor && rig.ref_sensor->type == kSensorCamera &&
        rig.ref_sensor->id == image.camera_id) {
      image.cam_from_world = frame.rig_from_world;
      continue;
    }
    const RigSensor* sensor = nullptr;
    for (const RigSensor& candidate : rig.other_sensors) {
      if (candidate.sensor.type == kSensorCamera &&
          candidate.sensor.id == image.camera_id) {
        sensor = &candidate;
      }
    }
    if (sensor == nullptr) {
      throw FormatError(where + ": camera_id " +
                        std::to_string(image.camera_id) +
                        " is not a sensor of the rig");
    }
    if (!sensor->sensor_from_rig) {
      throw FormatError(where + ": camera_id " +
                        std::to_string(image.camera_id) +
                        " has no sensor_from_rig, so the image has no pose");
    }
    const Rigid3d cam_from_world =
        *sensor->sensor_from_rig * frame.rig_from_world;
    image.cam_from_world = Rigid3d(cam_from_world.rotation.normalized(),
                                   cam_from_world.translation);
  }
}

}  // namespace odomcal::internal
