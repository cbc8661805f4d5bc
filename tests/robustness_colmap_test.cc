// Bad inputs and failures on the COLMAP path (`odomcal colmap` and `odomcal
// run` against fake colmap executables, one test against real COLMAP), one
// test per row of the COLMAP section of docs/robustness.md; the fixture is
// robustness_fixture.h.
#include "odomcal/tests/robustness_fixture.h"

namespace odomcal::robustness_test {
namespace {

TEST_F(Robustness, ColmapMissingFromPath) {
  WriteImageFolder(5, "x");
  ExpectColmapFailure(
      RunOdomcal(RunCommand(), {{"PATH=" + Path("empty_bin")}}),
      std::string(kRunError) +
          "COLMAP not found: 'colmap' is not an executable on PATH (install "
          "Debian's colmap package or pass --colmap_path)");
}

// Extraction and matching succeed, the mapper aborts on a failed CHECK
// (exit 134) and prints glog's stack trace after it.
TEST_F(Robustness, ColmapAbortsMidRun) {
  WriteImageFolder(5, "x");
  const std::string bin = WriteFakeColmap(
      "if [ \"$1\" = feature_extractor ]; then cp " + WritePreparedDatabase() +
      " \"$3\"; fi\n"
      "if [ \"$1\" = mapper ]; then\n"
      "  echo 'F0101 mapper.cc:1] Check failed: reconstruction' >&2\n"
      "  echo '*** Check failure stack trace: ***' >&2\n"
      "  echo '    @     0x55aebb39816f  colmap::IncrementalMapper::Run()' "
      ">&2\n"
      "  exit 134\n"
      "fi\n"
      "exit 0\n");
  const CommandResult run = RunOdomcal(RunCommand({"--matcher", "sequential"}),
                                       {{"PATH=" + bin + ":/usr/bin:/bin"}});
  ExpectColmapFailure(
      run,
      std::string(kRunError) +
          "COLMAP mapper failed with exit code 134 (COLMAP aborted on a "
          "failed CHECK); see " +
          Path("ws/logs/mapper_seed_0.log") +
          " (last line: F0101 mapper.cc:1] Check failed: reconstruction)");
}

// COLMAP exits 0 but writes nothing: caught after the first stage; and a
// mapper that exits 0 without a model.
TEST_F(Robustness, ColmapProducesNoModel) {
  WriteImageFolder(5, "x");
  std::string bin = WriteFakeColmap("exit 0\n");
  CommandResult run = RunOdomcal(RunCommand({"--matcher", "sequential"}),
                                 {{"PATH=" + bin + ":/usr/bin:/bin"}});
  ExpectColmapFailure(run,
                      std::string(kRunError) +
                          "COLMAP feature_extractor wrote no database " +
                          Path("ws/database.db") + " (see " +
                          Path("ws/logs/feature_extractor.log") + ")");

  bin = WriteFakeColmap("if [ \"$1\" = feature_extractor ]; then cp " +
                        WritePreparedDatabase() + " \"$3\"; fi\nexit 0\n");
  run = RunOdomcal(RunCommand({"--matcher", "sequential"}),
                   {{"PATH=" + bin + ":/usr/bin:/bin"}});
  // Seed 0, the initialisation ladder's one rung here (the database has no
  // verified pairs to choose an initial pair from), seeds 1 and 2.
  ExpectColmapFailure(
      run,
      std::string(kRunError) +
          "COLMAP mapper produced no model in 4 runs (tried: COLMAP's "
          "initial pair search, relaxed initialisation tests) (see " +
          Path("ws/logs/mapper_seed_0.log") +
          "): COLMAP's log is empty; too little texture or overlap, or wrong "
          "intrinsics");
}

// COLMAP's mapper returns, for one random seed, no model, for another a model
// with two images registered 3 deg off (the odometry contradicts the motion
// pairs around them), for a third a clean one: odomcal maps with seed 0,
// starts it again with relaxed initialisation tests (no model either), maps
// with seeds 1 and 2 and calibrates the clean model, copied to sparse/.
TEST_F(Robustness, MapperRunsAgainWhileTheOdometryContradictsItsModel) {
  constexpr int kImages = 30;
  const SimulatedDrive drive = WriteImageFolder(kImages, "x");
  WriteMapperModel(drive, kImages, "seed_1", {7, 19});
  WriteMapperModel(drive, kImages, "seed_2");
  const std::string bin = WriteFakeColmapWithMapperModels();
  const CommandResult run = RunOdomcal(RunCommand({"--matcher", "sequential"}),
                                       {{"PATH=" + bin + ":/usr/bin:/bin"}});
  ASSERT_EQ(run.exit_code, 0) << run.out << run.err;
  EXPECT_NE(run.out.find("--random_seed 1 ... done"), std::string::npos)
      << run.out;
  EXPECT_NE(run.out.find("contradict the odometry: mapping again"),
            std::string::npos)
      << run.out;
  const json result = json::parse(ReadFile(Path("ws/calibration.json")));
  EXPECT_EQ(result["status"], "success");
  // The default frame spacing follows the narrower (here the vertical)
  // field of view of --camera_params 260,260,160,120: 2 atan(120 / 260).
  const double fov_deg = 2.0 * std::atan(120.0 / 260.0) * kRadToDeg;
  EXPECT_NEAR(result["options"]["run"]["frame_min_rotation_deg"].get<double>(),
              fov_deg / 8.0,
              1e-9);
  EXPECT_NEAR(result["options"]["run"]["frame_min_translation_m"].get<double>(),
              2.5 * std::tan(fov_deg / 16.0 * kDegToRad),
              1e-9);
  const json& attempts = result["colmap"]["mapper_attempts"];
  ASSERT_EQ(attempts.size(), 4u) << attempts.dump(2);
  EXPECT_FALSE(attempts[0]["produced_model"]);
  EXPECT_EQ(attempts[0]["failure_cause"], "COLMAP's log is empty");
  EXPECT_EQ(attempts[0]["initialization"], "colmap_search");
  // The ladder's run, recorded after the seeds.
  EXPECT_FALSE(attempts[3]["produced_model"]);
  EXPECT_EQ(attempts[3]["initialization"], "relaxed_search");
  EXPECT_EQ(attempts[3]["random_seed"], 0);
  EXPECT_NE(run.out.find("COLMAP mapping the drive again (1 of 1 ways to "
                         "start): COLMAP's initial pair search, the initial "
                         "pair's tests relaxed"),
            std::string::npos)
      << run.out;
  EXPECT_TRUE(attempts[1]["produced_model"]);
  EXPECT_GT(attempts[1]["num_contradicting_pairs"], 0) << attempts.dump(2);
  EXPECT_EQ(attempts[2]["num_contradicting_pairs"], 0) << attempts.dump(2);
  EXPECT_EQ(attempts[2]["num_pairs_used"], attempts[2]["num_motion_pairs"]);
  EXPECT_FALSE(attempts[0]["chosen"]);
  EXPECT_FALSE(attempts[1]["chosen"]);
  EXPECT_TRUE(attempts[2]["chosen"]);
  EXPECT_EQ(ReadFile(dir_ / "ws" / "sparse" / "0" / "images.bin"),
            ReadFile(dir_ / "models" / "seed_2" / "images.bin"));
  EXPECT_EQ(result["colmap"]["sub_models"][0]["path"], Path("ws/sparse/0"));
  EXPECT_LT(ExtrinsicRotationError(result, drive), 0.1 * kPi / 180.0);
}

// `odomcal run` against the command line of COLMAP 3.8 and of 4.1.1 (the
// renames of 3.13: FeatureExtraction/FeatureMatching for the device and
// thread options, Mapper.image_list_path, default_random_seed and
// Mapper.random_seed): every stage accepts what odomcal passes, the seeds
// reach the mapper, and the result names the version.
class ColmapCommandLine : public Robustness {
 protected:
  void ExpectRunAgainstColmap(const std::string& version) {
    constexpr int kImages = 30;
    const SimulatedDrive drive = WriteImageFolder(kImages, "x");
    WriteMapperModel(drive, kImages, "seed_1", {7, 19});
    WriteMapperModel(drive, kImages, "seed_2");
    const std::string bin = WriteStrictFakeColmap(version);
    const CommandResult run =
        RunOdomcal(RunCommand({"--matcher", "sequential"}),
                   {{"PATH=" + bin + ":/usr/bin:/bin"}});
    ASSERT_EQ(run.exit_code, 0) << version << "\n" << run.out << run.err;
    const json result = json::parse(ReadFile(Path("ws/calibration.json")));
    EXPECT_EQ(result["status"], "success");
    EXPECT_LT(ExtrinsicRotationError(result, drive), 0.1 * kPi / 180.0);
    const std::string commands = ReadFile(Path("ws/commands.txt"));
    const bool v4 = version == "4.1";
    for (const char* name :
         {"--SiftExtraction.max_num_features", "--Mapper.num_threads"}) {
      EXPECT_NE(commands.find(name), std::string::npos) << name;
    }
    EXPECT_NE(commands.find(v4 ? "--FeatureMatching.use_gpu"
                               : "--SiftMatching.use_gpu"),
              std::string::npos);
    EXPECT_NE(commands.find(v4 ? "--default_random_seed 1" : "--random_seed 1"),
              std::string::npos)
        << commands;
    // Seed 1 mapped (seed 0 has no model, nor the initialisation ladder's
    // run with relaxed tests, whose options the version took; seed 1's
    // contradicts the odometry): the seeds reached the mapper.
    EXPECT_EQ(result["colmap"]["mapper_attempts"].size(), 4u);
    EXPECT_NE(commands.find("--Mapper.init_max_forward_motion 1"),
              std::string::npos)
        << commands;
    EXPECT_EQ(result["colmap"]["version"], v4 ? "4.1.1" : "3.8.0");
  }
};

TEST_F(ColmapCommandLine, RunsAgainstTheCommandLineOfColmap3Point8) {
  ExpectRunAgainstColmap("3.8");
}

TEST_F(ColmapCommandLine, RunsAgainstTheCommandLineOfColmap4Point1) {
  ExpectRunAgainstColmap("4.1");
}

// --mapper global with COLMAP 4.1: `colmap global_mapper` with its
// GlobalMapper.* options (and no Mapper.*), the seeds passed as
// --GlobalMapper.random_seed, the mapper named in the JSON.
TEST_F(ColmapCommandLine, GlobalMapperOfColmap4Point1) {
  constexpr int kImages = 30;
  const SimulatedDrive drive = WriteImageFolder(kImages, "x");
  WriteMapperModel(drive, kImages, "seed_1", {7, 19});
  WriteMapperModel(drive, kImages, "seed_2");
  const std::string bin = WriteStrictFakeColmap("4.1");
  const CommandResult run =
      RunOdomcal(RunCommand({"--matcher", "sequential", "--mapper", "global"}),
                 {{"PATH=" + bin + ":/usr/bin:/bin"}});
  ASSERT_EQ(run.exit_code, 0) << run.out << run.err;
  const json result = json::parse(ReadFile(Path("ws/calibration.json")));
  EXPECT_EQ(result["status"], "success");
  EXPECT_LT(ExtrinsicRotationError(result, drive), 0.1 * kPi / 180.0);
  EXPECT_EQ(result["colmap"]["mapper"], "global_mapper");
  EXPECT_EQ(result["options"]["run"]["mapper"], "global");
  EXPECT_EQ(result["colmap"]["mapper_attempts"].size(), 3u);
  const std::string commands = ReadFile(Path("ws/commands.txt"));
  EXPECT_NE(commands.find(" global_mapper --database_path "), std::string::npos)
      << commands;
  EXPECT_NE(commands.find("--GlobalMapper.random_seed 2"), std::string::npos);
  EXPECT_NE(run.out.find("reconstructed by: COLMAP 4.1.1 (global_mapper)"),
            std::string::npos)
      << run.out;
}

// --mapper global with COLMAP 3.8, which has no global_mapper: the
// standalone glomap maps the database (one attempt: it has no seed).
TEST_F(ColmapCommandLine, GlomapBesideColmap3Point8) {
  constexpr int kImages = 30;
  const SimulatedDrive drive = WriteImageFolder(kImages, "x");
  WriteMapperModel(drive, kImages, "seed_0");
  const std::string bin = WriteStrictFakeColmap("3.8");
  WriteStrictFakeGlomap();
  const CommandResult run =
      RunOdomcal(RunCommand({"--matcher", "sequential", "--mapper", "global"}),
                 {{"PATH=" + bin + ":/usr/bin:/bin"}});
  ASSERT_EQ(run.exit_code, 0) << run.out << run.err;
  const json result = json::parse(ReadFile(Path("ws/calibration.json")));
  EXPECT_EQ(result["status"], "success");
  EXPECT_LT(ExtrinsicRotationError(result, drive), 0.1 * kPi / 180.0);
  EXPECT_EQ(result["colmap"]["mapper"], "glomap mapper");
  EXPECT_EQ(result["colmap"]["mapper_attempts"].size(), 1u);
  EXPECT_NE(run.out.find("one mapper attempt (glomap has no random seed)"),
            std::string::npos)
      << run.out;
  const std::string commands = ReadFile(Path("ws/commands.txt"));
  EXPECT_NE(commands.find("glomap mapper --database_path "), std::string::npos)
      << commands;
}

// Without glomap, --mapper global with COLMAP 3.8 is one clear error.
TEST_F(ColmapCommandLine, GlobalMapperWithoutGlomapIsOneClearError) {
  constexpr int kImages = 30;
  const SimulatedDrive drive = WriteImageFolder(kImages, "x");
  WriteMapperModel(drive, kImages, "seed_0");
  const std::string bin = WriteStrictFakeColmap("3.8");
  const CommandResult run = RunOdomcal(RunCommand({"--matcher",
                                                   "sequential",
                                                   "--mapper",
                                                   "global",
                                                   "--glomap_path",
                                                   Path("no_such_glomap")}),
                                       {{"PATH=" + bin + ":/usr/bin:/bin"}});
  EXPECT_NE(run.exit_code, 0);
  EXPECT_NE(run.err.find("GLOMAP not found"), std::string::npos) << run.err;
}

// A drive of more selected images than --chunk_images is mapped in chunks
// (mapper_chunks.h): 60 images, chunks of at most 50 sharing 12: images
// 1-37 and 24-60, each mapped once (--random_seed 0; the fake mapper gives
// the whole drive's model both times), each cut to its own images (1-30,
// 30-60: the overlap split in the middle, one image shared) as a sub-model
// of its own; the calibration of the two segments recovers the extrinsic.
TEST_F(Robustness, LongDriveIsMappedInChunks) {
  constexpr int kImages = 60;
  const SimulatedDrive drive = WriteImageFolder(kImages, "x");
  WriteMapperModel(drive, kImages, "seed_0");
  const std::string bin = WriteFakeColmapWithMapperModels(true);
  const CommandResult run = RunInChunksOf50(bin, 2);
  ASSERT_EQ(run.exit_code, 0) << run.out << run.err;
  EXPECT_NE(run.out.find("60 images: mapped in 2 chunks of 37 sharing at "
                         "least 12 images"),
            std::string::npos)
      << run.out;
  EXPECT_NE(run.out.find("COLMAP mapping chunk 2 of 2 (images 24-60)"),
            std::string::npos)
      << run.out;
  EXPECT_NE(run.out.find("60 of 37 images registered, 31 of the chunk's own "
                         "31 kept"),
            std::string::npos)
      << run.out;
  EXPECT_NE(run.out.find("calibrating against the odometry (models of the 2 "
                         "chunks)"),
            std::string::npos)
      << run.out;
  // --num_threads 2: both chunks mapped side by side (chunk 0's fake
  // mapper gives a model only so), one thread each.
  EXPECT_NE(run.out.find("2 chunks mapped, 2 side by side (--num_threads 2)"),
            std::string::npos)
      << run.out;
  const std::string commands = ReadFile(Path("ws/commands.txt"));
  for (const std::string chunk : {"chunk_0", "chunk_1"}) {
    EXPECT_NE(commands.find("mapper_attempts/" + chunk + " --image_list_path " +
                            Path("ws/chunks/" + chunk + "_images.txt") +
                            " --random_seed 0 --Mapper.num_threads 1 "),
              std::string::npos)
        << commands;
  }
  const json result = json::parse(ReadFile(Path("ws/calibration.json")));
  EXPECT_EQ(result["status"], "success");
  EXPECT_EQ(result["options"]["run"]["chunk_images"], 50);
  const json& sub_models = result["colmap"]["sub_models"];
  ASSERT_EQ(sub_models.size(), 2u) << sub_models.dump(2);
  EXPECT_EQ(sub_models[0]["num_registered_images"], 30);
  EXPECT_EQ(sub_models[1]["num_registered_images"], 31);
  EXPECT_EQ(result["colmap"]["image_coverage"]["num_in_calibration"], 60);
  EXPECT_LT(ExtrinsicRotationError(result, drive), 0.1 * kPi / 180.0);
}

// A chunk whose model COLMAP folded is mapped again with the next seed
// (mapper_chunks.h): with --random_seed 0 the mapper gives two sub-models,
// images 1-15 and 16-60, the second with images 41, 43, 45 and 47 3 deg
// off, so the pairs 40-48 of the second chunk's own images (30-60)
// contradict the odometry as one stretch, left out as folded; the first
// chunk's own images (1-30) are clean. The fold is in the combination's
// third sub-model (the first chunk's two, then the second chunk's one that
// keeps its own images), which came from the second chunk: only that chunk
// is mapped again (--random_seed 1, a clean model), and its new model is
// kept: every image is in the calibration. The fake COLMAP's
// bundle_adjuster writes nothing, so posing the fold from the odometry
// (tried first) fails, and the seeds take over.
TEST_F(Robustness, ChunkWithAFoldedStretchIsMappedAgain) {
  constexpr int kImages = 60;
  const SimulatedDrive drive = WriteImageFolder(kImages, "x");
  WriteMapperModel(drive, 15, "seed_0/0");
  WriteMapperModel(drive, kImages, "seed_0/1", {40, 42, 44, 46}, 15);
  WriteMapperModel(drive, kImages, "seed_1");
  const std::string bin = WriteFakeColmapWithMapperModels();
  const CommandResult run = RunInChunksOf50(bin, 2);
  ASSERT_EQ(run.exit_code, 0) << run.out << run.err;
  EXPECT_EQ(run.out.find("COLMAP mapping chunk 1 again"), std::string::npos)
      << run.out;
  EXPECT_NE(run.out.find("not posed: colmap bundle_adjuster wrote no model"),
            std::string::npos)
      << run.out;
  EXPECT_NE(run.out.find("COLMAP mapping chunk 2 again, --random_seed 1 ("),
            std::string::npos)
      << run.out;
  EXPECT_NE(run.out.find(": this model kept"), std::string::npos) << run.out;
  const json result = json::parse(ReadFile(Path("ws/calibration.json")));
  EXPECT_EQ(result["status"], "success");
  const json& attempts = result["colmap"]["mapper_attempts"];
  ASSERT_EQ(attempts.size(), 2u) << attempts.dump(2);
  EXPECT_TRUE(attempts[0]["chunk"].is_null());
  EXPECT_EQ(attempts[0]["random_seed"], 0);
  EXPECT_GE(attempts[0]["num_pairs_left_out"].get<int>(), 3);
  EXPECT_FALSE(attempts[0]["chosen"].get<bool>());
  EXPECT_EQ(attempts[1]["chunk"], 1);
  EXPECT_EQ(attempts[1]["random_seed"], 1);
  // The combination calibrated: chunk 0's model and chunk 1's new one.
  EXPECT_EQ(attempts[1]["path"], Path("ws/mapper_attempts/chunks_1_seed_1"));
  EXPECT_TRUE(fs::exists(Path("ws/mapper_attempts/chunk_1_seed_1/0")));
  EXPECT_EQ(attempts[1]["num_pairs_left_out"], 0);
  EXPECT_TRUE(attempts[1]["chosen"].get<bool>());
  EXPECT_EQ(result["colmap"]["image_coverage"]["num_in_calibration"], 60);
  EXPECT_LT(ExtrinsicRotationError(result, drive), 0.1 * kPi / 180.0);
}

// The same fold, and no seed that would give a model: the folded stretch is
// posed again from the odometry first (images 39 on, from the calibration of
// the first combination), triangulated and adjusted again (the fake keeps the
// poses it is given), and that model is kept without any mapper run again.
TEST_F(Robustness, ChunkWithAFoldedStretchIsPosedFromTheOdometry) {
  constexpr int kImages = 60;
  const SimulatedDrive drive = WriteImageFolder(kImages, "x");
  WriteMapperModel(drive, 15, "seed_0/0");
  WriteMapperModel(drive, kImages, "seed_0/1", {40, 42, 44, 46}, 15);
  WriteMapperModel(drive, kImages, "triangulated", {}, 15, 30);
  const std::string bin = WriteFakeColmapWithMapperModels(false, true);
  const CommandResult run = RunInChunksOf50(bin, 2);
  ASSERT_EQ(run.exit_code, 0) << run.out << run.err;
  EXPECT_NE(run.out.find("COLMAP chunk 2: the folded stretch posed from the "
                         "odometry, triangulated and adjusted again ("),
            std::string::npos)
      << run.out;
  EXPECT_NE(run.out.find("images from 000039.png on; 0 motion pairs of the "
                         "drive left out as folded (was "),
            std::string::npos)
      << run.out;
  EXPECT_NE(run.out.find(": this model kept"), std::string::npos) << run.out;
  EXPECT_EQ(run.out.find("again, --random_seed"), std::string::npos) << run.out;
  const std::string commands = ReadFile(Path("ws/commands.txt"));
  EXPECT_TRUE(Contains(commands, "point_triangulator")) << commands;
  EXPECT_TRUE(Contains(commands, "--clear_points 1")) << commands;
  EXPECT_TRUE(Contains(commands,
                       "bundle_adjuster --input_path " +
                           Path("ws/mapper_attempts/"
                                "chunk_1_posed_from_odometry/triangulated_0")))
      << commands;
  EXPECT_TRUE(Contains(commands, "--BundleAdjustment.refine_focal_length 0"))
      << commands;
  const json result = json::parse(ReadFile(Path("ws/calibration.json")));
  EXPECT_EQ(result["status"], "success");
  const json& attempts = result["colmap"]["mapper_attempts"];
  ASSERT_EQ(attempts.size(), 2u) << attempts.dump(2);
  EXPECT_FALSE(attempts[0]["posed_from_odometry"].get<bool>());
  EXPECT_GE(attempts[0]["num_pairs_left_out"].get<int>(), 3);
  EXPECT_EQ(attempts[1]["chunk"], 1);
  EXPECT_EQ(attempts[1]["random_seed"], 0);
  EXPECT_TRUE(attempts[1]["posed_from_odometry"].get<bool>());
  EXPECT_EQ(attempts[1]["path"],
            Path("ws/mapper_attempts/chunks_1_posed_from_odometry"));
  EXPECT_EQ(attempts[1]["num_pairs_left_out"], 0);
  EXPECT_TRUE(attempts[1]["chosen"].get<bool>());
  EXPECT_EQ(result["colmap"]["image_coverage"]["num_in_calibration"], 60);
  EXPECT_LT(ExtrinsicRotationError(result, drive), 0.1 * kPi / 180.0);

  // Run again: the same fold posed the same way, so COLMAP's two stages
  // are reused (their output is not written anew) and so is every later
  // stage; the result is the same.
  // A sub-model left from an earlier run with more of them must not be
  // combined.
  const fs::path adjusted =
      Path("ws/mapper_attempts/chunk_1_posed_from_odometry/0/images.bin");
  const auto written = fs::last_write_time(adjusted);
  const fs::path stale =
      Path("ws/mapper_attempts/chunk_1_posed_from_odometry/1");
  fs::copy(adjusted.parent_path(), stale);
  const CommandResult rerun = RunInChunksOf50(bin, 2);
  ASSERT_EQ(rerun.exit_code, 0) << rerun.out << rerun.err;
  EXPECT_EQ(fs::last_write_time(adjusted), written);
  EXPECT_FALSE(fs::exists(stale));
  const json again = json::parse(ReadFile(Path("ws/calibration.json")));
  EXPECT_EQ(again["odom_from_cam"], result["odom_from_cam"]);
  EXPECT_TRUE(again["colmap"]["mapper_attempts"][1]["chosen"].get<bool>());
}

// The same, but the adjustment leaves the posed images without the points
// that would hold them (29 each, one fewer than COLMAP's mapper registers an
// image from): their poses would be the odometry's, agreeing with it by
// construction, so the posed model is not used and the fold stays left out.
TEST_F(Robustness, PosedStretchWithoutPointsToHoldItIsNotUsed) {
  constexpr int kImages = 60;
  const SimulatedDrive drive = WriteImageFolder(kImages, "x");
  WriteMapperModel(drive, 15, "seed_0/0");
  WriteMapperModel(drive, kImages, "seed_0/1", {40, 42, 44, 46}, 15);
  WriteMapperModel(drive, kImages, "triangulated", {}, 15, 29);
  const std::string bin = WriteFakeColmapWithMapperModels(false, true);
  const CommandResult run = RunInChunksOf50(bin, 2);
  ASSERT_EQ(run.exit_code, 0) << run.out << run.err;
  EXPECT_NE(run.out.find("sees only 29 triangulated points after the "
                         "adjustment"),
            std::string::npos)
      << run.out;
  EXPECT_NE(run.out.find("contradicts the odometry: left out"),
            std::string::npos)
      << run.out;
  const json result = json::parse(ReadFile(Path("ws/calibration.json")));
  for (const json& attempt : result["colmap"]["mapper_attempts"]) {
    EXPECT_FALSE(attempt["posed_from_odometry"].get<bool>());
  }
  EXPECT_LT(result["colmap"]["image_coverage"]["num_in_calibration"].get<int>(),
            60);
}

// Where a second seed folds the chunk too (here worse), the fold is the
// scene's: no third seed is tried (it would be clean here), and the first
// model stays, its folded stretch left out and named.
TEST_F(Robustness, ChunkFoldedByTwoSeedsIsNotMappedAThirdTime) {
  constexpr int kImages = 60;
  const SimulatedDrive drive = WriteImageFolder(kImages, "x");
  WriteMapperModel(drive, kImages, "seed_0", {40, 42, 44, 46});
  WriteMapperModel(drive, kImages, "seed_1", {36, 38, 40, 42, 44, 46, 48, 50});
  WriteMapperModel(drive, kImages, "seed_2");
  const std::string bin = WriteFakeColmapWithMapperModels();
  const CommandResult run = RunInChunksOf50(bin);
  ASSERT_EQ(run.exit_code, 0) << run.out << run.err;
  EXPECT_NE(run.out.find(": not better, no further seed"), std::string::npos)
      << run.out;
  EXPECT_EQ(run.out.find("--random_seed 2"), std::string::npos) << run.out;
  EXPECT_NE(run.out.find("contradicts the odometry: left out"),
            std::string::npos)
      << run.out;
  const json result = json::parse(ReadFile(Path("ws/calibration.json")));
  const json& attempts = result["colmap"]["mapper_attempts"];
  ASSERT_EQ(attempts.size(), 2u) << attempts.dump(2);
  EXPECT_TRUE(attempts[0]["chosen"].get<bool>());
  EXPECT_EQ(attempts[1]["chunk"], 1);
  EXPECT_FALSE(attempts[1]["chosen"].get<bool>());
  EXPECT_LT(attempts[1]["num_pairs_used"], attempts[0]["num_pairs_used"]);
  // What was calibrated is the first model.
  EXPECT_EQ(result["diagnostics"]["num_pairs_used"],
            attempts[0]["num_pairs_used"]);
  EXPECT_LT(result["colmap"]["image_coverage"]["num_in_calibration"].get<int>(),
            60);
}

// COLMAP reconstructed images 20-29 twice: in sub-model 0 on their own,
// two of them 3 deg off, and in sub-model 1 with all the others. Sub-model
// 0 is left out as a duplicate (its motions would count twice, and its
// misregistered images would make the clean model look contradicted), so
// the first mapper run is accepted and calibrated.
TEST_F(Robustness, DuplicateSubModelIsLeftOut) {
  constexpr int kImages = 30;
  const SimulatedDrive drive = WriteImageFolder(kImages, "x");
  WriteMapperModel(drive, kImages, "seed_0/0", {22, 25}, /*first=*/20);
  WriteMapperModel(drive, kImages, "seed_0/1");
  const std::string bin = WriteFakeColmapWithMapperModels();
  const CommandResult run = RunOdomcal(RunCommand({"--matcher", "sequential"}),
                                       {{"PATH=" + bin + ":/usr/bin:/bin"}});
  ASSERT_EQ(run.exit_code, 0) << run.out << run.err;
  const json result = json::parse(ReadFile(Path("ws/calibration.json")));
  EXPECT_EQ(result["status"], "success");
  const json& colmap = result["colmap"];
  ASSERT_EQ(colmap["sub_models"].size(), 1u) << colmap.dump(2);
  EXPECT_EQ(colmap["sub_models"][0]["name"], "1");
  ASSERT_EQ(colmap["duplicate_sub_models"].size(), 1u) << colmap.dump(2);
  EXPECT_EQ(colmap["duplicate_sub_models"][0]["name"], "0");
  EXPECT_EQ(colmap["duplicate_sub_models"][0]["duplicate_of"], "1");
  EXPECT_EQ(colmap["duplicate_sub_models"][0]["num_registered_images"], 10);
  ASSERT_EQ(colmap["mapper_attempts"].size(), 1u) << colmap.dump(2);
  EXPECT_EQ(colmap["mapper_attempts"][0]["num_contradicting_pairs"], 0);
  EXPECT_TRUE(ContainsName(
      result["warnings"],
      "sub-model 0 (10 images) holds no image that sub-model 1 does "
      "not: left out as a second reconstruction of the same images"))
      << result["warnings"].dump(2);
  EXPECT_TRUE(fs::exists(dir_ / "ws" / "sparse_metric" / "1"));
  EXPECT_FALSE(fs::exists(dir_ / "ws" / "sparse_metric" / "0"));
}

// Every run contradicted elsewhere: the least contradicted model is
// calibrated, with a warning (here without matching again). Contradicted
// where the previous run was: the mapping stops (another seed changed
// nothing); new matches contradicted there too end it (the odometry or the
// images are at fault). --mapper_attempts 1 maps once.
TEST_F(Robustness, MapperModelsAllContradictedAreReported) {
  constexpr int kImages = 30;
  const SimulatedDrive drive = WriteImageFolder(kImages, "x");
  WriteMapperModel(drive, kImages, "seed_0", {7, 19});
  WriteMapperModel(drive, kImages, "seed_1", {12});
  WriteMapperModel(drive, kImages, "seed_2", {4, 15, 23});
  const std::string bin = WriteFakeColmapWithMapperModels();
  const auto run_in_fresh_workspace =
      [&](const std::vector<std::string>& extra) {
        fs::remove_all(dir_ / "ws");
        std::vector<std::string> flags = {"--matcher", "sequential"};
        flags.insert(flags.end(), extra.begin(), extra.end());
        const CommandResult run =
            RunOdomcal(RunCommand(flags), {{"PATH=" + bin + ":/usr/bin:/bin"}});
        EXPECT_EQ(run.exit_code, 0) << run.out << run.err;
        return json::parse(ReadFile(Path("ws/calibration.json")));
      };
  json result = run_in_fresh_workspace({"--rematch", "off"});
  json attempts = result["colmap"]["mapper_attempts"];
  ASSERT_EQ(attempts.size(), 3u);
  EXPECT_TRUE(attempts[1]["chosen"]) << attempts.dump(2);
  EXPECT_LT(attempts[1]["num_contradicting_pairs"],
            attempts[0]["num_contradicting_pairs"]);
  EXPECT_TRUE(
      ContainsName(result["warnings"],
                   "every one of 3 COLMAP mapper runs gave motion pairs that "
                   "contradict the odometry; the model of --random_seed 1 "
                   "contradicts it least"))
      << result["warnings"].dump(2);
  EXPECT_FALSE(fs::exists(dir_ / "ws" / "database_rematched.db"));

  WriteMapperModel(drive, kImages, "seed_1", {7, 19});
  result = run_in_fresh_workspace({"--rematch", "off"});
  attempts = result["colmap"]["mapper_attempts"];
  ASSERT_EQ(attempts.size(), 2u) << attempts.dump(2);
  EXPECT_TRUE(attempts[0]["chosen"]);
  EXPECT_EQ(attempts[1]["num_pairs_left_out"], 0);
  EXPECT_TRUE(ContainsName(
      result["warnings"],
      "COLMAP mapper runs with --random_seed 0 and 1 gave the same " +
          attempts[1]["num_contradicting_pairs"].dump() +
          " motion pairs that contradict the odometry: the odometry or the "
          "images "
          "disagree there, not COLMAP's randomness"))
      << result["warnings"].dump(2);
  EXPECT_FALSE(fs::exists(dir_ / "ws" / "database_rematched.db"));

  // The new matches contradicted at the same pairs again: no second seed.
  WriteMapperModel(drive, kImages, "rematch_seed_0", {7, 19});
  WriteMapperModel(drive, kImages, "rematch_seed_1");
  result = run_in_fresh_workspace({});
  attempts = result["colmap"]["mapper_attempts"];
  ASSERT_EQ(attempts.size(), 3u) << attempts.dump(2);
  EXPECT_TRUE(attempts[0]["chosen"]);
  EXPECT_EQ(attempts[2]["matching_round"], 1);
  EXPECT_TRUE(ContainsName(result["warnings"],
                           "COLMAP mapper runs on two matchings (--random_seed "
                           "0, --random_seed 0 on the new "
                           "matches) gave the same " +
                               attempts[2]["num_contradicting_pairs"].dump() +
                               " motion pairs that contradict the odometry: "
                               "the odometry or the images "
                               "disagree there, not COLMAP's randomness"))
      << result["warnings"].dump(2);

  result =
      run_in_fresh_workspace({"--mapper_attempts", "1", "--rematch", "off"});
  EXPECT_EQ(result["colmap"]["mapper_attempts"].size(), 1u);
}

// The stage markers record a stage's arguments, not the lists its arguments
// name: a rerun on the same workspace with other frames (a changed
// image_list.txt) must run the stages anew, not reuse the old features and
// models; a rerun with the same frames reuses every stage.
TEST_F(Robustness, RerunWithOtherFramesRunsTheStagesAnew) {
  constexpr int kImages = 30;
  const SimulatedDrive drive = WriteImageFolder(kImages, "x");
  WriteMapperModel(drive, kImages, "seed_0");
  const std::string bin = WriteFakeColmapWithMapperModels();
  const RunLimits environment = {{"PATH=" + bin + ":/usr/bin:/bin"}};
  const std::vector<std::string> flags = {"--matcher", "sequential"};
  CommandResult run = RunOdomcal(RunCommand(flags), environment);
  ASSERT_EQ(run.exit_code, 0) << run.out << run.err;
  const std::string first_list = ReadFile(dir_ / "ws" / "image_list.txt");

  run = RunOdomcal(RunCommand(flags), environment);
  ASSERT_EQ(run.exit_code, 0) << run.out << run.err;
  EXPECT_EQ(run.out.find("... done"), std::string::npos) << run.out;

  std::vector<std::string> spaced = flags;
  spaced.insert(spaced.end(), {"--frame_min_translation_m", "0.3"});
  run = RunOdomcal(RunCommand(spaced), environment);
  EXPECT_NE(ReadFile(dir_ / "ws" / "image_list.txt"), first_list);
  EXPECT_NE(run.out.find("COLMAP feature extraction ... done"),
            std::string::npos)
      << run.out;
  EXPECT_EQ(run.out.find("reused from an earlier run"), std::string::npos)
      << run.out;
}

// The seeds give three models contradicted each elsewhere: odomcal matches
// again, into database_rematched.db (a copy, cleaned of matches, so that
// database.db keeps the first matches), and maps that. Rerun on the same
// workspace, every stage is reused. When the new matches are contradicted too,
// the least contradicted model of either matching is calibrated, with a warning
// naming both.
TEST_F(Robustness, MatchesAgainWhenTheSeedsDoNotHelp) {
  constexpr int kImages = 30;
  const SimulatedDrive drive = WriteImageFolder(kImages, "x");
  WriteMapperModel(drive, kImages, "seed_0", {7, 19});
  WriteMapperModel(drive, kImages, "seed_1", {12, 20});
  WriteMapperModel(drive, kImages, "seed_2", {4, 15, 23});
  WriteMapperModel(drive, kImages, "rematch_seed_0", {5, 25});
  WriteMapperModel(drive, kImages, "rematch_seed_1");
  const std::string bin = WriteFakeColmapWithMapperModels();
  const RunLimits environment = {{"PATH=" + bin + ":/usr/bin:/bin"}};
  CommandResult run =
      RunOdomcal(RunCommand({"--matcher", "sequential"}), environment);
  ASSERT_EQ(run.exit_code, 0) << run.out << run.err;
  EXPECT_NE(
      run.out.find(
          "COLMAP sequential matching again, into a copy of the features ... "
          "done"),
      std::string::npos)
      << run.out;
  EXPECT_NE(
      run.out.find("COLMAP mapping the new matches, --random_seed 1 ... done"),
      std::string::npos)
      << run.out;
  json result = json::parse(ReadFile(Path("ws/calibration.json")));
  EXPECT_EQ(result["status"], "success");
  json attempts = result["colmap"]["mapper_attempts"];
  ASSERT_EQ(attempts.size(), 5u) << attempts.dump(2);
  for (int i = 0; i < 5; ++i) {
    EXPECT_EQ(attempts[i]["matching_round"], i < 3 ? 0 : 1) << attempts.dump(2);
    EXPECT_EQ(attempts[i]["chosen"], i == 4) << attempts.dump(2);
  }
  EXPECT_EQ(attempts[4]["path"], Path("ws/mapper_attempts/rematch_seed_1"));
  EXPECT_EQ(attempts[4]["num_contradicting_pairs"], 0);
  EXPECT_EQ(ReadFile(dir_ / "ws" / "sparse" / "0" / "images.bin"),
            ReadFile(dir_ / "models" / "rematch_seed_1" / "images.bin"));
  EXPECT_TRUE(result["warnings"].empty()) << result["warnings"].dump(2);
  const std::string commands = ReadFile(dir_ / "ws" / "commands.txt");
  EXPECT_NE(commands.find("database_cleaner --type matches --database_path " +
                          Path("ws/database_rematched.db")),
            std::string::npos)
      << commands;
  EXPECT_NE(commands.find("sequential_matcher --database_path " +
                          Path("ws/database_rematched.db")),
            std::string::npos)
      << commands;
  EXPECT_NE(commands.find("mapper --database_path " +
                          Path("ws/database_rematched.db")),
            std::string::npos)
      << commands;
  EXPECT_TRUE(fs::exists(dir_ / "ws" / "database.db"));

  run = RunOdomcal(RunCommand({"--matcher", "sequential"}), environment);
  ASSERT_EQ(run.exit_code, 0) << run.out << run.err;
  EXPECT_EQ(run.out.find("... done"), std::string::npos) << run.out;
  EXPECT_EQ(ReadFile(dir_ / "ws" / "commands.txt"), commands);

  WriteMapperModel(drive, kImages, "rematch_seed_1", {kImages - 1});  // 1 pair
  fs::remove_all(dir_ / "models" / "rematch_seed_2");
  fs::remove_all(dir_ / "ws");
  run = RunOdomcal(RunCommand({"--matcher", "sequential"}), environment);
  ASSERT_EQ(run.exit_code, 0) << run.out << run.err;
  result = json::parse(ReadFile(Path("ws/calibration.json")));
  attempts = result["colmap"]["mapper_attempts"];
  ASSERT_EQ(attempts.size(), 6u) << attempts.dump(2);
  EXPECT_TRUE(attempts[4]["chosen"]) << attempts.dump(2);
  EXPECT_TRUE(ContainsName(
      result["warnings"],
      "every one of 6 COLMAP mapper runs on two matchings gave motion "
      "pairs that contradict the odometry; the model of --random_seed 1 "
      "on the new matches contradicts it least"))
      << result["warnings"].dump(2);
  // The misregistered last image is in no pair the odometry confirms: it is
  // left out of the metric model.
  EXPECT_TRUE(ContainsName(
      result["warnings"],
      "sparse_metric/0: left out 1 image whose every motion pair the "
      "odometry contradicts (" +
          ImageName(kImages - 1) + ")"))
      << result["warnings"].dump(2);
  const ColmapModel metric = ReadColmapModel(Path("ws/sparse_metric/0"));
  EXPECT_EQ(metric.images.size(), static_cast<size_t>(kImages - 1));
  for (const auto& [id, image] : metric.images)
    EXPECT_NE(image.name, ImageName(kImages - 1));
}

// Real COLMAP on files that are not images: feature_extractor skips every
// one and exits 0. Skipped without colmap on PATH.
TEST_F(Robustness, UnreadableImagesWithRealColmap) {
  if (std::system("colmap help > /dev/null 2>&1") != 0) {
    GTEST_SKIP() << "colmap is not installed";
  }
  WriteImageFolder(5, "this is not a PNG file\n");
  const CommandResult run = RunOdomcal(RunCommand());
  ExpectColmapFailure(
      run,
      std::string(kRunError) + "COLMAP could read none of the 5 images in " +
          Path("images") + " (see " + Path("ws/logs/feature_extractor.log") +
          ": ERROR: Failed to read image file format.)");
}

// ---------------------------------------------------------------------------
// Outputs.

}  // namespace
// `run --bag` takes the images, their times and the odometry from the bag:
// the flags that give them otherwise are refused, before any file is read.
TEST_F(Robustness, RunWithABagAndAnImageFolderIsRefused) {
  WriteFile(fs::path(Path("drive.bag")), "#ROSBAG V2.0\n");
  fs::create_directories(Path("images"));
  ExpectBadInput(
      RunOdomcal({"run",
                  "--bag",
                  Path("drive.bag"),
                  "--image_path",
                  Path("images"),
                  "--workspace_path",
                  Path("ws")}),
      "odomcal run: error: --bag gives the images, their times and the "
      "odometry: drop --image_path");
  ExpectBadInput(RunOdomcal({"run",
                             "--workspace_path",
                             Path("ws"),
                             "--odometry",
                             Path("drive.bag")}),
                 "odomcal run: error: --image_path is required (or --bag)");
  EXPECT_FALSE(fs::exists(Path("ws")));
}

}  // namespace odomcal::robustness_test
