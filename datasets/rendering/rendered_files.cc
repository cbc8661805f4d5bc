#include "odomcal/adapters/timestamp.h"
#include "odomcal/adapters/trajectory_io.h"
#include "odomcal/datasets/rendering/rendered_files_internal.h"

#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include <filesystem>
#include <fstream>
#include <stdexcept>

namespace odomcal::internal {

nlohmann::json TransformJson(const Rigid3d& transform) {
  const Eigen::Quaterniond q = WithPositiveScalar(transform.rotation);
  const Eigen::Vector3d& t = transform.translation;
  const Eigen::Matrix4d m = transform.ToMatrix();
  nlohmann::json matrix = nlohmann::json::array();
  for (int r = 0; r < 4; ++r) {
    matrix.push_back({m(r, 0), m(r, 1), m(r, 2), m(r, 3)});
  }
  return {{"quaternion_wxyz", {q.w(), q.x(), q.y(), q.z()}},
          {"translation_m", {t.x(), t.y(), t.z()}},
          {"matrix", matrix}};
}

nlohmann::json IntrinsicsJson(const CameraIntrinsics& camera) {
  return {{"model", camera.ColmapModelName()},
          {"width", camera.width},
          {"height", camera.height},
          {"params", camera.ColmapParams()},
          {"param_names", camera.ColmapParamNames()}};
}

nlohmann::json FrameJson(const RenderedFrame& frame) {
  nlohmann::json pose = TransformJson(frame.origin_from_cam);
  pose.erase("matrix");
  return {{"name", frame.image_name},
          {"timestamp", FormatTimestampSeconds(frame.stamp_ns)},
          {"capture_timestamp", FormatTimestampSeconds(frame.capture_ns)},
          {"world_from_cam", pose}};
}

void WriteTextFile(const std::string& path, const std::string& text) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out << text;
  out.close();
  if (!out) throw std::runtime_error(path + ": write failed");
}

void WritePng(const Image& image, const std::string& path) {
  const cv::Mat rgb(image.height,
                    image.width,
                    CV_8UC3,
                    const_cast<uint8_t*>(image.rgb.data()));
  cv::Mat bgr;
  cv::cvtColor(rgb, bgr, cv::COLOR_RGB2BGR);
  bool written = false;
  try {
    written = cv::imwrite(path, bgr);
  } catch (const cv::Exception& e) {
    throw std::runtime_error(path + ": cannot write the image (" + e.what() +
                             ")");
  }
  if (!written) throw std::runtime_error(path + ": cannot write the image");
}

void WriteOdometryFiles(const RenderedDataset& dataset,
                        const std::string& output_dir) {
  const std::filesystem::path root(output_dir);
  WriteOdometryCsv(dataset.odometry, (root / "odometry.csv").string());
  WriteOdometryCsv(dataset.true_odometry,
                   (root / "odometry_ground_truth.csv").string());
  if (!dataset.true_odometry_se3.poses.empty()) {
    WriteTumTrajectory(dataset.true_odometry_se3,
                       (root / "odometry_se3.tum").string());
  }
}

}  // namespace odomcal::internal
