// The binary model files: a fixture built byte by byte, the writer's bytes,
// and truncated, garbled or trailing bytes.
#include "odomcal/adapters/colmap_model.h"
#include "odomcal/adapters/colmap_model_test_support.h"
#include "odomcal/adapters/format_error.h"
#include "odomcal/adapters/test_support.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <filesystem>
#include <stdexcept>
#include <string>
#include <vector>

namespace odomcal {
namespace {

namespace fs = std::filesystem;
using namespace colmap_test;  // NOLINT(google-build-using-namespace)

TEST(ColmapModel, BinaryFixtureBuiltByteByByte) {
  ExpectFixture(ReadColmapModel(WriteBinaryFixture("binary_fixture")));
}

TEST(ColmapModel, WriterProducesColmapsBinaryLayout) {
  ColmapModel model = ReadColmapModel(WriteBinaryFixture("binary_layout_in"));
  // Write the stored (unnormalised) quaternion, to compare with the fixture
  // bytes: the writer normalises, so give it the already-normal one.
  const std::string dir = FreshDir("binary_layout_out");
  WriteColmapModel(model, dir, ColmapFormat::kBinary);
  EXPECT_EQ(ReadBytes(dir + "/cameras.bin"), FixtureCamerasBin().data);
  EXPECT_EQ(ReadBytes(dir + "/points3D.bin"), FixturePointsBin().data);
  // images.bin: same size and layout; only the quaternion of image 9 differs
  // (the fixture stores it unnormalised).
  const Eigen::Quaterniond q =
      model.images.at(9).cam_from_world.rotation.normalized();
  Bytes expected;
  expected.U64(2);
  expected.U32(2).F64(1).F64(0).F64(0).F64(0).F64(0).F64(0).F64(0);
  expected.U32(4).Text("frames/img_a.png").U8(0).U64(0);
  expected.U32(9).F64(q.w()).F64(q.x()).F64(q.y()).F64(q.z());
  expected.F64(0.5).F64(-1).F64(2).U32(4).Text("frames/img_b.png").U8(0);
  expected.U64(2).F64(100.5).F64(200.25).U64(77).F64(3).F64(4).U64(
      ~uint64_t{0});
  EXPECT_EQ(ReadBytes(dir + "/images.bin"), expected.data);
}

// Every proper prefix of every binary file must fail with the file's name,
// never crash or read past the end.
TEST(ColmapModel, TruncatedBinaryFilesFailNamingTheFile) {
  const std::string source = FreshDir("truncate_source");
  WriteColmapModel(MakeModel(), source, ColmapFormat::kBinary);
  const std::string dir = FreshDir("truncate");
  for (const char* name : {"cameras.bin", "images.bin", "points3D.bin"}) {
    const std::string full = ReadBytes(source + "/" + name);
    ASSERT_GT(full.size(), 100u);
    for (const char* other : {"cameras.bin", "images.bin", "points3D.bin"}) {
      fs::copy_file(source + "/" + other,
                    dir + "/" + other,
                    fs::copy_options::overwrite_existing);
    }
    for (size_t size = 0; size < full.size(); ++size) {
      WriteFile(dir + "/" + name, full.substr(0, size));
      const std::string error = FormatErrorOf([&] { ReadColmapModel(dir); });
      ASSERT_TRUE(Contains(error, dir + "/" + name + ": byte "))
          << "size " << size << ": " << error;
      ASSERT_EQ(error.find('\n'), std::string::npos) << error;
    }
  }
}

TEST(ColmapModel, GarbledCountsFailBeforeAllocating) {
  const uint64_t kHuge = uint64_t{1} << 60;
  struct Case {
    const char* file;
    size_t count_offset;  // byte offset of the uint64 count to garble
    const char* what;
  };
  // Offsets into the fixture: the file counts, image 9's num_points2D
  // (8 + 4 + 56 + 4 + 17 bytes in), point 77's track length (8 + 8 + 24 + 3
  // + 8).
  const Case cases[] = {{"cameras.bin", 0, "number of cameras"},
                        {"images.bin", 0, "number of images"},
                        {"images.bin", 89, "number of points2D"},
                        {"points3D.bin", 0, "number of points3D"},
                        {"points3D.bin", 51, "track length"}};
  for (const Case& c : cases) {
    SCOPED_TRACE(std::string(c.file) + " " + c.what);
    const std::string dir = WriteBinaryFixture("garbled");
    std::string bytes = ReadBytes(dir + "/" + c.file);
    Bytes huge;
    huge.U64(kHuge);
    bytes.replace(c.count_offset, 8, huge.data);
    WriteFile(dir + "/" + c.file, bytes);
    const std::string error = FormatErrorOf([&] { ReadColmapModel(dir); });
    EXPECT_TRUE(Contains(
        error,
        dir + "/" + c.file + ": byte " + std::to_string(c.count_offset) + ": "))
        << error;
    EXPECT_TRUE(
        Contains(error, std::string(c.what) + " is " + std::to_string(kHuge)))
        << error;
    EXPECT_TRUE(Contains(error, "remaining bytes hold at most")) << error;
  }
}

TEST(ColmapModel, BinaryTrailingBytesAndBadValuesAreRejected) {
  {
    const std::string dir = WriteBinaryFixture("trailing");
    WriteFile(dir + "/cameras.bin", FixtureCamerasBin().F64(1.0).data);
    const std::string error = FormatErrorOf([&] { ReadColmapModel(dir); });
    EXPECT_TRUE(Contains(error, "cameras.bin: byte 64: 8 unexpected bytes"))
        << error;
  }
  {
    const std::string dir = WriteBinaryFixture("nan_param");
    Bytes cameras;
    cameras.U64(1).U32(4).U32(2).U64(640).U64(480);
    cameras.F64(500).F64(std::nan("")).F64(240).F64(0.01);
    WriteFile(dir + "/cameras.bin", cameras.data);
    const std::string error = FormatErrorOf([&] { ReadColmapModel(dir); });
    EXPECT_TRUE(Contains(error,
                         "cameras.bin: byte 40: camera 1 of 1 "
                         "(camera_id 4): param is not finite"))
        << error;
  }
  {
    const std::string dir = WriteBinaryFixture("bad_quaternion");
    std::string bytes = FixtureImagesBin().data;
    Bytes zero;
    zero.F64(0.0);
    bytes.replace(8 + 4, 8, zero.data);  // QW of image 9: norm 0.37
    WriteFile(dir + "/images.bin", bytes);
    const std::string error = FormatErrorOf([&] { ReadColmapModel(dir); });
    EXPECT_TRUE(Contains(error,
                         "(image_id 9): quaternion (QW QX QY QZ) has "
                         "norm"))
        << error;
  }
  {
    const std::string dir = WriteBinaryFixture("missing_camera");
    std::string bytes = FixtureImagesBin().data;
    Bytes camera_id;
    camera_id.U32(5);
    bytes.replace(8 + 4 + 56, 4, camera_id.data);
    WriteFile(dir + "/images.bin", bytes);
    const std::string error = FormatErrorOf([&] { ReadColmapModel(dir); });
    EXPECT_TRUE(
        Contains(error, "camera_id 5 is not in " + dir + "/cameras.bin"))
        << error;
  }
  {
    const std::string dir = WriteBinaryFixture("unterminated_name");
    Bytes images;
    images.U64(1).U32(9);
    for (int k = 0; k < 7; ++k) images.F64(k == 0 ? 1.0 : 0.0);
    images.U32(4).Text(std::string(64, 'x'));
    WriteFile(dir + "/images.bin", images.data);
    const std::string error = FormatErrorOf([&] { ReadColmapModel(dir); });
    EXPECT_TRUE(Contains(error, "name has no terminating")) << error;
  }
}

}  // namespace
}  // namespace odomcal
