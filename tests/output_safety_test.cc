// No odomcal command overwrites or deletes a user's input, and --overwrite
// replaces only what odomcal wrote (docs/robustness.md, "Outputs never touch
// inputs"). Each refusal asserts the exact error line, exit code 2, and that
// the inputs are byte-identical afterwards; every refusal comes before any
// work, so no command here needs COLMAP.

#include "odomcal/adapters/colmap_model.h"
#include "odomcal/adapters/test_support.h"
#include "odomcal/adapters/timestamp.h"
#include "odomcal/adapters/trajectory_io.h"
#include "odomcal/datasets/simulation/drive_simulator.h"
#include "odomcal/tests/odomcal_process.h"
#include "odomcal/tests/scratch_folder_test.h"
#include "odomcal/tests/test_files.h"

#include <unistd.h>

#include <gtest/gtest.h>

#include <filesystem>
#include <string>
#include <vector>

namespace odomcal {
namespace {

namespace fs = std::filesystem;

constexpr char kNeverOverInput[] = "; odomcal never writes over an input";
constexpr char kForeign[] = "; --overwrite replaces only odomcal's own files";

class OutputSafety : public ScratchFolderTest {
 protected:
  OutputSafety() : ScratchFolderTest("odomcal_outputs_") {}

  // WriteFile, creating the folders on the way.
  void WriteNew(const std::string& name, const std::string& bytes) const {
    fs::create_directories(fs::path(Path(name)).parent_path());
    WriteFile(Path(name), bytes);
  }

  // `camera` (TUM) and `odometry` (CSV) of a 60 s simulated drive.
  SimulatedDrive WriteDrive(
      const std::string& camera = "camera.tum",
      const std::string& odometry = "odometry.csv") const {
    DriveSimulatorOptions options;
    options.camera_rotation_noise_deg = 0.01;
    options.camera_position_noise = 0.0005;
    const SimulatedDrive drive = SimulateDrive(options);
    fs::create_directories(fs::path(Path(camera)).parent_path());
    fs::create_directories(fs::path(Path(odometry)).parent_path());
    WriteTumTrajectory(drive.camera, Path(camera));
    WriteOdometryCsv(drive.odometry, Path(odometry));
    return drive;
  }

  std::vector<std::string> Calibrate(const std::string& camera,
                                     const std::string& output) const {
    return {"calibrate",
            "--camera_poses",
            Path(camera),
            "--odometry",
            Path("odometry.csv"),
            "--output",
            Path(output),
            "--overwrite"};
  }

  // A binary COLMAP model of every second camera pose in `model_folder`, its
  // image_timestamps.csv and odometry.csv in dir_.
  void WriteColmapModelFolder(const std::string& model_folder) const {
    const SimulatedDrive drive = WriteDrive();
    ColmapModel model;
    model.cameras[1] = MakeColmapCamera(
        1, ColmapCameraModel::kPinhole, 320, 240, {260, 260, 160, 120});
    std::string stamps = "image_name,timestamp\n";
    for (size_t i = 0; i < drive.camera.poses.size(); i += 2) {
      ColmapImage image;
      image.image_id = static_cast<uint32_t>(i + 1);
      image.camera_id = 1;
      image.name = std::to_string(100000 + i) + ".png";
      image.cam_from_world = Inverse(drive.camera.poses[i].world_from_sensor);
      model.images[image.image_id] = image;
      stamps += image.name + "," +
                FormatTimestampSeconds(drive.camera.poses[i].stamp_ns) + "\n";
    }
    fs::create_directories(Path(model_folder));
    WriteColmapModel(model, Path(model_folder), ColmapFormat::kBinary);
    WriteFile(Path("image_timestamps.csv"), stamps);
  }

  std::vector<std::string> Colmap(const std::string& model,
                                  const std::string& output) const {
    return {"colmap",
            "--model_path",
            Path(model),
            "--odometry",
            Path("odometry.csv"),
            "--image_timestamps",
            Path("image_timestamps.csv"),
            "--output_path",
            Path(output),
            "--overwrite"};
  }

  // images/ with three files, odometry.csv and image_timestamps.csv in
  // `folder`, and `odomcal run` on them into `workspace`.
  std::vector<std::string> Run(const std::string& folder,
                               const std::string& workspace) const {
    WriteDrive("camera.tum", folder + "/odometry.csv");
    fs::create_directories(Path(folder + "/images"));
    for (const char* name : {"000000.png", "000001.png", "000002.png"}) {
      WriteFile(Path(folder + "/images/" + name),
                "not decoded before the refusal");
    }
    WriteFile(Path(folder + "/image_timestamps.csv"),
              "000000.png,1700000001\n000001.png,1700000002\n"
              "000002.png,1700000003\n");
    return {"run",
            "--image_path",
            Path(folder + "/images"),
            "--odometry",
            Path(folder + "/odometry.csv"),
            "--image_timestamps",
            Path(folder + "/image_timestamps.csv"),
            "--workspace_path",
            Path(workspace)};
  }
};

// The user's case: the odometry given as --output with --overwrite.
TEST_F(OutputSafety, CalibrateOutputIsTheOdometry) {
  WriteDrive();
  const auto before = Snapshot(dir_);
  ExpectBadInput(RunOdomcal(Calibrate("camera.tum", "odometry.csv")),
                 "odomcal calibrate: error: " + Path("odometry.csv") +
                     " (--output) is the input " + Path("odometry.csv") +
                     " (--odometry)" + kNeverOverInput);
  EXPECT_EQ(Snapshot(dir_), before);
}

// The user's case: camera poses named result.yaml, --output result.json: the
// YAML written beside the JSON would replace them.
TEST_F(OutputSafety, CalibrateYamlBesideTheOutputIsTheCameraPoses) {
  WriteDrive("result.yaml");
  const auto before = Snapshot(dir_);
  ExpectBadInput(RunOdomcal(Calibrate("result.yaml", "result.json")),
                 "odomcal calibrate: error: " + Path("result.yaml") +
                     " (the YAML beside --output) is the input " +
                     Path("result.yaml") + " (--camera_poses)" +
                     kNeverOverInput);
  EXPECT_EQ(Snapshot(dir_), before);
  EXPECT_FALSE(fs::exists(Path("result.json")));
}

// The user's case: the model in P/sparse_metric/0 (beside COLMAP's
// project.ini), --output_path P: writing would replace the model.
TEST_F(OutputSafety, ColmapOutputFolderHoldsTheInputModel) {
  WriteColmapModelFolder("P/sparse_metric/0");
  WriteNew("P/project.ini", "[General]\n");
  const auto before = Snapshot(dir_);
  ExpectBadInput(RunOdomcal(Colmap("P/sparse_metric/0", "P")),
                 "odomcal colmap: error: " + Path("P") +
                     " (--output_path) holds the input " +
                     Path("P/sparse_metric/0") +
                     " (--model_path); odomcal never writes into a folder that "
                     "holds an input");
  EXPECT_EQ(Snapshot(dir_), before);
}

TEST_F(OutputSafety, SymbolicLinkToAnInput) {
  WriteDrive();
  fs::create_symlink(Path("odometry.csv"), Path("link.json"));
  fs::create_directory_symlink(dir_, Path("same_folder"));
  fs::copy_file(Path("camera.tum"), Path("camera.yaml"));
  const auto before = Snapshot(dir_);
  ExpectBadInput(
      RunOdomcal(Calibrate("camera.tum", "link.json")),
      "odomcal calibrate: error: " + Path("link.json") +
          " (--output) resolves through a symbolic link to the input " +
          Path("odometry.csv") + " (--odometry)" + kNeverOverInput);
  // The YAML beside the output, through a linked folder.
  ExpectBadInput(
      RunOdomcal(Calibrate("camera.yaml", "same_folder/camera.json")),
      "odomcal calibrate: error: " + Path("same_folder/camera.yaml") +
          " (the YAML beside --output) resolves through a symbolic link to the "
          "input " +
          Path("camera.yaml") + " (--camera_poses)" + kNeverOverInput);
  EXPECT_EQ(Snapshot(dir_), before);
}

TEST_F(OutputSafety, HardLinkToAnInput) {
  WriteDrive();
  fs::create_hard_link(Path("odometry.csv"), Path("hard.json"));
  const auto before = Snapshot(dir_);
  ExpectBadInput(RunOdomcal(Calibrate("camera.tum", "hard.json")),
                 "odomcal calibrate: error: " + Path("hard.json") +
                     " (--output) is a hard link to the input " +
                     Path("odometry.csv") + " (--odometry)" + kNeverOverInput);
  EXPECT_EQ(Snapshot(dir_), before);
}

// --output r.yaml: the YAML beside it is the same file.
TEST_F(OutputSafety, OutputIsAnotherOutput) {
  WriteDrive();
  ExpectBadInput(RunOdomcal(Calibrate("camera.tum", "r.yaml")),
                 "odomcal calibrate: error: " + Path("r.yaml") +
                     " (the YAML beside --output) is the output " +
                     Path("r.yaml") +
                     " (--output); two outputs cannot share a file");
  EXPECT_FALSE(fs::exists(Path("r.yaml")));
}

TEST_F(OutputSafety, OutputFolderInsideAnInputFolder) {
  const std::vector<std::string> arguments = Run("data", "data/images/ws");
  const auto before = Snapshot(dir_);
  ExpectBadInput(RunOdomcal(arguments),
                 "odomcal run: error: " + Path("data/images/ws") +
                     " (--workspace_path) is inside the input folder " +
                     Path("data/images") +
                     " (--image_path); odomcal never writes into an input");
  EXPECT_EQ(Snapshot(dir_), before);
  EXPECT_FALSE(fs::exists(Path("data/images/ws")));
}

TEST_F(OutputSafety, InputInsideTheOutputFolder) {
  const std::vector<std::string> arguments = Run("data", "data");
  const auto before = Snapshot(dir_);
  ExpectBadInput(RunOdomcal(arguments),
                 "odomcal run: error: " + Path("data") +
                     " (--workspace_path) holds the input " +
                     Path("data/images") +
                     " (--image_path); odomcal never writes into a folder that "
                     "holds an input");
  EXPECT_EQ(Snapshot(dir_), before);
}

// Files odomcal did not write are never replaced, with or without
// --overwrite: a JSON of the user's, a COLMAP model and project.ini in an
// output folder, COLMAP's database.db in a workspace, files in the output
// folders of simulate and render.
TEST_F(OutputSafety, OverwriteRefusesForeignFiles) {
  WriteColmapModelFolder("project/sparse/0");
  WriteFile(Path("mine.json"), "{\"the user's\": true}\n");
  WriteNew("out/project.ini", "[General]\n");
  WriteColmapModelFolder("out/sparse_metric/0");
  WriteNew("ws/database.db", "the user's COLMAP database");
  WriteNew("sim/divergence.csv", "the user's table");
  WriteNew("render/images/000000.png", "the user's image");
  const auto before = Snapshot(dir_);

  ExpectBadInput(RunOdomcal(Calibrate("camera.tum", "mine.json")),
                 "odomcal calibrate: error: " + Path("mine.json") +
                     ": exists and is not an odomcal result" + kForeign);
  const auto not_listed = [&](const std::string& folder) {
    return ": was not written by odomcal (not listed in " +
           Path(folder + "/.odomcal_outputs") + ")" + kForeign;
  };
  ExpectBadInput(RunOdomcal(Colmap("project/sparse", "out")),
                 "odomcal colmap: error: " + Path("out/sparse_metric") +
                     not_listed("out"));
  std::vector<std::string> run = Run("data", "ws");
  ExpectBadInput(
      RunOdomcal(run),
      "odomcal run: error: " + Path("ws/database.db") + not_listed("ws"));
  ExpectBadInput(RunOdomcal({"simulate",
                             "--output_path",
                             Path("sim"),
                             "--trials",
                             "1",
                             "--sweep",
                             "num_motions",
                             "--overwrite"}),
                 "odomcal simulate: error: " + Path("sim/divergence.csv") +
                     not_listed("sim"));
  ExpectBadInput(
      RunOdomcal({"render",
                  "--preset",
                  "small",
                  "--output_path",
                  Path("render"),
                  "--overwrite"}),
      "odomcal render: error: " + Path("render/images") + not_listed("render"));
  auto after = Snapshot(dir_);
  for (const char* folder : {"data"}) {  // written by Run() after `before`
    for (auto it = after.begin(); it != after.end();) {
      it = it->first.rfind(Path(folder), 0) == 0 ? after.erase(it)
                                                 : std::next(it);
    }
  }
  EXPECT_EQ(after, before);
}

// --overwrite still replaces what odomcal wrote, and only that: a user's
// file beside odomcal's outputs survives; reruns of demo reuse its folder.
TEST_F(OutputSafety, OverwriteReplacesOdomcalsOwnOutputs) {
  WriteColmapModelFolder("project/sparse/0");
  ASSERT_EQ(RunOdomcal(Calibrate("camera.tum", "result.json")).exit_code, 0);
  WriteFile(Path("result.json"), ReadFile(Path("result.json")) + " ");
  ASSERT_EQ(RunOdomcal(Calibrate("camera.tum", "result.json")).exit_code, 0);
  EXPECT_NE(ReadFile(Path("result.json")).back(), ' ') << "not replaced";

  const std::vector<std::string> colmap = Colmap("project/sparse", "out");
  const CommandResult first = RunOdomcal(colmap);
  ASSERT_EQ(first.exit_code, 0) << first.err;
  WriteFile(Path("out/notes.txt"), "the user's");
  WriteFile(Path("out/report.html"), "stale");
  const auto project = Snapshot(Path("project"));
  const CommandResult second = RunOdomcal(colmap);
  ASSERT_EQ(second.exit_code, 0) << second.err;
  EXPECT_NE(ReadFile(Path("out/report.html")), "stale");
  EXPECT_EQ(ReadFile(Path("out/notes.txt")), "the user's");
  EXPECT_TRUE(fs::exists(Path("out/sparse_metric/0/images.bin")));
  EXPECT_EQ(Snapshot(Path("project")), project);

  // A short drive: what is tested is which files a rerun replaces (the
  // default 120 s drive took 100 s of CI's sanitizer run for two demos).
  const std::vector<std::string> demo = {"demo",
                                         "--simulated",
                                         "--duration_s",
                                         "30",
                                         "--workspace_path",
                                         Path("demo")};
  ASSERT_EQ(RunOdomcal(demo).exit_code, 0);
  WriteFile(Path("demo/notes.txt"), "the user's");
  const CommandResult again = RunOdomcal(demo);
  EXPECT_EQ(again.exit_code, 0) << again.err;
  EXPECT_EQ(ReadFile(Path("demo/notes.txt")), "the user's");
}

}  // namespace
}  // namespace odomcal
