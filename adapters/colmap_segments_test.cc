#include "odomcal/adapters/colmap_segments.h"

#include "odomcal/adapters/colmap_model.h"
#include "odomcal/adapters/format_error.h"
#include "odomcal/adapters/test_support.h"
#include "odomcal/solver/rigid3.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <functional>
#include <map>
#include <string>
#include <vector>

namespace odomcal {
namespace {

namespace fs = std::filesystem;

// Composition and inversion of transforms of size ~10: double rounding only.
constexpr double kExactTolerance = 1e-12;
constexpr int64_t kBaseNs = 1403636579763555584;

std::string FreshDir(const std::string& name) {
  const fs::path dir =
      fs::path(::testing::TempDir()) / ("odomcal_colmap_segments_" + name);
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir.string();
}

Rigid3d PoseNumber(int k) {
  return Rigid3d(Eigen::Quaterniond(1.0, 0.1 * k, -0.05 * k, 0.2).normalized(),
                 Eigen::Vector3d(0.5 * k, -1.0 + k, 2.0 - 0.3 * k));
}

// A model whose images are (image_id, name, cam_from_world).
ColmapModel MakeModel(
    const std::vector<std::tuple<uint32_t, std::string, Rigid3d>>& images) {
  ColmapModel model;
  model.cameras[1] = MakeColmapCamera(
      1, ColmapCameraModel::kSimplePinhole, 64, 48, {50, 32, 24});
  for (const auto& [id, name, pose] : images) {
    ColmapImage image;
    image.image_id = id;
    image.name = name;
    image.camera_id = 1;
    image.cam_from_world = pose;
    model.images[id] = image;
  }
  return model;
}

// Stamps: image "cam0/00000k.png" at kBaseNs + k * 0.1 s.
ImageTimestamps Stamps(int count) {
  std::map<std::string, int64_t> table;
  for (int k = 1; k <= count; ++k) {
    table["cam0/00000" + std::to_string(k) + ".png"] =
        kBaseNs + k * 100000000LL;
  }
  return ImageTimestamps::FromTable(table, "stamps.csv");
}

std::string Name(int k) { return "cam0/00000" + std::to_string(k) + ".png"; }

void ExpectNear(const Rigid3d& a, const Rigid3d& b) {
  EXPECT_LT((a.ToMatrix() - b.ToMatrix()).cwiseAbs().maxCoeff(),
            kExactTolerance);
}

// sparse/0: images 1..4 (ids in reverse name order); sparse/1: images 4..6,
// image 4 shared with its own pose there. sparse/notes: ignored.
std::string MakeRoot(const std::string& name) {
  const std::string root = FreshDir(name);
  WriteColmapModel(MakeModel({{9, Name(1), PoseNumber(1)},
                              {5, Name(3), PoseNumber(3)},
                              {7, Name(2), PoseNumber(2)},
                              {2, Name(4), PoseNumber(4)}}),
                   root + "/0",
                   ColmapFormat::kBinary);
  WriteColmapModel(MakeModel({{1, Name(6), PoseNumber(16)},
                              {2, Name(5), PoseNumber(15)},
                              {3, Name(4), PoseNumber(14)}}),
                   root + "/1",
                   ColmapFormat::kText);
  fs::create_directories(root + "/notes");
  return root;
}

TEST(ReadColmapSegments, OneSegmentPerSubModelSharedImagesInEach) {
  const std::string root = MakeRoot("root");
  const std::vector<ColmapSegment> segments =
      ReadColmapSegments(root, Stamps(6));
  ASSERT_EQ(segments.size(), 2u);

  const ColmapSegment& first = segments[0];
  EXPECT_EQ(first.sub_model, "0");
  EXPECT_EQ(first.model_path, root + "/0");
  EXPECT_EQ(first.trajectory.source, root + "/0");
  EXPECT_FALSE(first.trajectory.planar);
  EXPECT_EQ(first.num_registered_images, 4);
  EXPECT_EQ(first.num_skipped_without_timestamp, 0);
  EXPECT_EQ(first.image_names,
            (std::vector<std::string>{Name(1), Name(2), Name(3), Name(4)}));
  EXPECT_EQ(first.image_ids, (std::vector<uint32_t>{9, 7, 5, 2}));
  ASSERT_EQ(first.trajectory.poses.size(), 4u);
  for (int k = 0; k < 4; ++k) {
    EXPECT_EQ(first.trajectory.poses[k].stamp_ns,
              kBaseNs + (k + 1) * 100000000LL);
    // world_from_cam is the inverse of the stored cam_from_world.
    ExpectNear(first.trajectory.poses[k].world_from_sensor,
               Inverse(PoseNumber(k + 1)));
  }

  const ColmapSegment& second = segments[1];
  EXPECT_EQ(second.sub_model, "1");
  EXPECT_EQ(second.image_names,
            (std::vector<std::string>{Name(4), Name(5), Name(6)}));
  EXPECT_EQ(second.image_ids, (std::vector<uint32_t>{3, 2, 1}));
  // The shared image carries each sub-model's own pose.
  ExpectNear(second.trajectory.poses[0].world_from_sensor,
             Inverse(PoseNumber(14)));
  ExpectNear(first.trajectory.poses[3].world_from_sensor,
             Inverse(PoseNumber(4)));
  EXPECT_EQ(second.trajectory.poses[0].stamp_ns,
            first.trajectory.poses[3].stamp_ns);
}

TEST(ReadColmapSegments, RelativeMotionsMatchColmapsConvention) {
  const std::string root = MakeRoot("relative");
  const ColmapModel model = ReadColmapModel(root + "/0");
  const ColmapSegment segment = ReadColmapSegments(root, Stamps(6))[0];
  for (size_t i = 0; i < segment.image_ids.size(); ++i) {
    for (size_t j = 0; j < segment.image_ids.size(); ++j) {
      const Rigid3d& cam_i_from_world =
          model.images.at(segment.image_ids[i]).cam_from_world;
      const Rigid3d& cam_j_from_world =
          model.images.at(segment.image_ids[j]).cam_from_world;
      const Rigid3d cam_i_from_cam_j =
          cam_i_from_world * Inverse(cam_j_from_world);
      ExpectNear(Inverse(segment.trajectory.poses[i].world_from_sensor) *
                     segment.trajectory.poses[j].world_from_sensor,
                 cam_i_from_cam_j);
    }
  }
}

TEST(ReadColmapSegments, ModelFolderGivenDirectly) {
  const std::string root = MakeRoot("direct");
  const std::vector<ColmapSegment> segments =
      ReadColmapSegments(root + "/1", Stamps(6));
  ASSERT_EQ(segments.size(), 1u);
  EXPECT_EQ(segments[0].sub_model, "");
  EXPECT_EQ(segments[0].model_path, root + "/1");
  EXPECT_EQ(segments[0].trajectory.poses.size(), 3u);
}

TEST(ReadColmapSegments, StampsFromFileNamesAndTimeOrderNotIdOrder) {
  const std::string root = FreshDir("file_names");
  // Name order differs from time order here ("10" < "9" as text).
  WriteColmapModel(MakeModel({{1, "left/10.png", PoseNumber(1)},
                              {2, "left/9.png", PoseNumber(2)},
                              {3, "left/11.png", PoseNumber(3)}}),
                   root + "/0",
                   ColmapFormat::kBinary);
  const ColmapSegment segment = ReadColmapSegments(
      root, ImageTimestamps::FromFileNames(TimeUnit::kSeconds))[0];
  EXPECT_EQ(
      segment.image_names,
      (std::vector<std::string>{"left/9.png", "left/10.png", "left/11.png"}));
  EXPECT_EQ(segment.trajectory.poses[0].stamp_ns, 9000000000);
}

TEST(ReadColmapSegments, ImagesWithoutTimestampFailOrAreSkipped) {
  const std::string root = MakeRoot("missing_stamp");
  const std::string error =
      FormatErrorOf([&] { ReadColmapSegments(root, Stamps(5)); });
  EXPECT_TRUE(Contains(error,
                       root + "/1: registered image '" + Name(6) +
                           "' has no timestamp: '" + Name(6) +
                           "' is not listed in stamps.csv"))
      << error;

  ColmapSegmentOptions options;
  options.skip_images_without_timestamp = true;
  const std::vector<ColmapSegment> segments =
      ReadColmapSegments(root, Stamps(5), options);
  EXPECT_EQ(segments[1].num_registered_images, 3);
  EXPECT_EQ(segments[1].num_skipped_without_timestamp, 1);
  EXPECT_EQ(segments[1].skipped_image_names, std::vector<std::string>{Name(6)});
  EXPECT_EQ(segments[1].trajectory.poses.size(), 2u);
  EXPECT_EQ(segments[0].num_skipped_without_timestamp, 0);
}

TEST(ReadColmapSegments, EqualStampsInOneSegmentAreRefused) {
  const std::string root = MakeRoot("equal_stamps");
  std::map<std::string, int64_t> table;
  for (int k = 1; k <= 6; ++k) table[Name(k)] = kBaseNs + k;
  table[Name(3)] = table[Name(2)];
  const std::string error = FormatErrorOf([&] {
    ReadColmapSegments(root, ImageTimestamps::FromTable(table, "t.csv"));
  });
  EXPECT_TRUE(Contains(error,
                       root + "/0: images '" + Name(2) + "' and '" + Name(3) +
                           "' have the same timestamp"))
      << error;
}

ColmapSegment SegmentOf(const std::string& sub_model,
                        const std::vector<int>& images) {
  ColmapSegment segment;
  segment.sub_model = sub_model;
  for (const int k : images) segment.image_names.push_back(Name(k));
  segment.num_registered_images = static_cast<int>(images.size());
  return segment;
}

std::vector<std::string> SubModels(const std::vector<ColmapSegment>& segments) {
  std::vector<std::string> names;
  for (const ColmapSegment& segment : segments)
    names.push_back(segment.sub_model);
  return names;
}

TEST(RemoveDuplicateSegments, MovesOutSubModelsALargerOneHoldsWhole) {
  // As COLMAP left the small preset: sub-model 0 a second copy of images
  // 6-9, which sub-model 1 holds among others; 2 shares only image 9.
  std::vector<ColmapSegment> segments = {
      SegmentOf("0", {6, 7, 8, 9}),
      SegmentOf("1", {1, 2, 3, 4, 5, 6, 7, 8, 9}),
      SegmentOf("2", {9, 10, 11})};
  const std::vector<DuplicateSegment> duplicates =
      RemoveDuplicateSegments(&segments);
  EXPECT_EQ(SubModels(segments), (std::vector<std::string>{"1", "2"}));
  ASSERT_EQ(duplicates.size(), 1u);
  EXPECT_EQ(duplicates[0].segment.sub_model, "0");
  EXPECT_EQ(duplicates[0].segment.image_names.size(), 4u);
  EXPECT_EQ(duplicates[0].duplicate_of, "1");
}

TEST(RemoveDuplicateSegments, KeepsTheFirstOfEqualsAndFollowsChains) {
  std::vector<ColmapSegment> segments = {SegmentOf("0", {1, 2}),
                                         SegmentOf("1", {1, 2, 3}),
                                         SegmentOf("2", {1, 2, 3}),
                                         SegmentOf("3", {}),
                                         SegmentOf("4", {1, 2, 3, 4})};
  const std::vector<DuplicateSegment> duplicates =
      RemoveDuplicateSegments(&segments);
  // An empty segment duplicates nothing: it stays.
  EXPECT_EQ(SubModels(segments), (std::vector<std::string>{"3", "4"}));
  ASSERT_EQ(duplicates.size(), 3u);
  for (const DuplicateSegment& duplicate : duplicates) {
    EXPECT_EQ(duplicate.duplicate_of, "4") << duplicate.segment.sub_model;
  }

  std::vector<ColmapSegment> equal = {SegmentOf("0", {1, 2}),
                                      SegmentOf("1", {1, 2})};
  const std::vector<DuplicateSegment> second = RemoveDuplicateSegments(&equal);
  EXPECT_EQ(SubModels(equal), (std::vector<std::string>{"0"}));
  ASSERT_EQ(second.size(), 1u);
  EXPECT_EQ(second[0].duplicate_of, "0");

  std::vector<ColmapSegment> disjoint = {SegmentOf("0", {1, 2}),
                                         SegmentOf("1", {3, 4})};
  EXPECT_TRUE(RemoveDuplicateSegments(&disjoint).empty());
  EXPECT_EQ(disjoint.size(), 2u);
}

TEST(FindColmapModelFolders, NumericOrderAndErrors) {
  const std::string root = FreshDir("order");
  for (const char* name : {"10", "2", "0"}) {
    WriteColmapModel(MakeModel({}), root + "/" + name, ColmapFormat::kText);
  }
  EXPECT_EQ(FindColmapModelFolders(root),
            (std::vector<std::string>{root + "/0", root + "/2", root + "/10"}));
  // An empty sub-model gives an empty segment.
  const std::vector<ColmapSegment> segments =
      ReadColmapSegments(root, Stamps(1));
  ASSERT_EQ(segments.size(), 3u);
  EXPECT_EQ(segments[2].sub_model, "10");
  EXPECT_TRUE(segments[2].trajectory.poses.empty());

  fs::create_directories(root + "/3");
  std::string error = FormatErrorOf([&] { FindColmapModelFolders(root); });
  EXPECT_TRUE(Contains(error,
                       root + "/3: numbered sub-folder without a "
                              "COLMAP model"))
      << error;

  const std::string empty = FreshDir("empty_root");
  fs::create_directories(empty + "/images");
  error = FormatErrorOf([&] { ReadColmapSegments(empty, Stamps(1)); });
  EXPECT_TRUE(Contains(error, empty + ": not a COLMAP sparse folder: neither"))
      << error;

  error = FormatErrorOf([&] { FindColmapModelFolders(empty + "/missing"); });
  EXPECT_TRUE(Contains(error,
                       empty + "/missing: not a COLMAP sparse folder: "
                               "no such directory"))
      << error;
}

}  // namespace
}  // namespace odomcal
