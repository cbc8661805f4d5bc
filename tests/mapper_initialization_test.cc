// The mapper's initialisation ladder (plugin/colmap/mapper_initialization.h)
// against a fake colmap whose mapper finds no initial pair of its own, as
// COLMAP 3.8's does on a forward drive ("No good initial image pair found"),
// and maps only from a pair it is given: odomcal passes the pair the
// odometry and the verified matches choose, and calibrates that model. The
// fixture is robustness_fixture.h; the section "When the mapper gives no
// model" of docs/cli.md.
#include "odomcal/adapters/colmap_database_order.h"
#include "odomcal/tests/robustness_fixture.h"

namespace odomcal::robustness_test {
namespace {

class MapperInitialization : public Robustness {
 protected:
  // Verified pairs (image ids in name order) with their inliers, no
  // essential matrix, in the prepared database. (odomcal renumbers the
  // images of a database without matches; this one has them already.)
  void AddVerifiedPairs(
      const std::vector<std::tuple<int, int, int>>& pairs) const {
    RenumberColmapImagesByName(WritePreparedDatabase());
    sqlite3* db = nullptr;
    ASSERT_EQ(sqlite3_open(WritePreparedDatabase().c_str(), &db), SQLITE_OK);
    std::string sql =
        "CREATE TABLE two_view_geometries (pair_id INTEGER PRIMARY KEY NOT "
        "NULL, rows INTEGER NOT NULL, cols INTEGER NOT NULL, data BLOB, config "
        "INTEGER NOT NULL, F BLOB, E BLOB, H BLOB, qvec BLOB, tvec BLOB);";
    for (const auto& [id1, id2, inliers] : pairs) {
      sql += "INSERT INTO two_view_geometries VALUES (" +
             std::to_string(int64_t{2147483647} * id1 + id2) + ", " +
             std::to_string(inliers) +
             ", 2, NULL, 2, NULL, NULL, NULL, NULL, "
             "NULL);";
    }
    EXPECT_EQ(sqlite3_exec(db, sql.c_str(), nullptr, nullptr, nullptr),
              SQLITE_OK)
        << sqlite3_errmsg(db);
    sqlite3_close(db);
  }

  // The mapper maps models/given only with Mapper.init_image_id1/2, whose
  // values it appends to init_pairs.txt; without them it says what COLMAP
  // 3.8 says when no pair passes its tests.
  std::string WriteFakeColmapWithoutInitialPair() const {
    return WriteFakeColmap("if [ \"$1\" = feature_extractor ]; then cp " +
                           WritePreparedDatabase() +
                           " \"$3\"; fi\n"
                           "if [ \"$1\" = mapper ]; then\n"
                           "  id1=''; id2=''\n"
                           "  while [ $# -gt 0 ]; do\n"
                           "    case \"$1\" in --output_path) out=\"$2\";;\n"
                           "      --Mapper.init_image_id1) id1=\"$2\";;\n"
                           "      --Mapper.init_image_id2) id2=\"$2\";; esac\n"
                           "    shift\n"
                           "  done\n"
                           "  if [ -n \"$id1\" ]; then\n"
                           "    echo \"$id1 $id2\" >> " +
                           Path("init_pairs.txt") +
                           "\n"
                           "    mkdir -p \"$out/0\" && cp " +
                           Path("models/given") +
                           "/* \"$out/0/\"\n"
                           "  else\n"
                           "    echo '  => No good initial image pair found.'\n"
                           "  fi\n"
                           "fi\n"
                           "exit 0\n");
  }
};

TEST_F(MapperInitialization, StartsFromTheOdometrysPairWhenColmapFindsNone) {
  constexpr int kImages = 30;
  const SimulatedDrive drive = WriteImageFolder(kImages, "x");
  WriteMapperModel(drive, kImages, "given");
  // Pair (3, 12) has the most inliers times baseline; (5, 6) has more
  // inliers but a short baseline; (1, 2) too few inliers to start from.
  AddVerifiedPairs({{1, 2, 90}, {5, 6, 800}, {3, 12, 400}, {7, 9, 300}});
  const std::string bin = WriteFakeColmapWithoutInitialPair();
  const CommandResult run = RunOdomcal(RunCommand({"--matcher",
                                                   "sequential",
                                                   "--frame_min_translation_m",
                                                   "0",
                                                   "--frame_min_rotation_deg",
                                                   "0"}),
                                       {{"PATH=" + bin + ":/usr/bin:/bin"}});
  ASSERT_EQ(run.exit_code, 0) << run.out << run.err;
  EXPECT_NE(run.out.find("COLMAP mapping the drive again (1 of "),
            std::string::npos)
      << run.out;
  // One mapper run with a given pair: the best one, which gave a model.
  EXPECT_EQ(ReadFile(dir_ / "init_pairs.txt"), "3 12\n");
  const json result = json::parse(ReadFile(Path("ws/calibration.json")));
  EXPECT_EQ(result["status"], "success");
  const json& attempts = result["colmap"]["mapper_attempts"];
  ASSERT_GE(attempts.size(), 2u) << attempts.dump(2);
  // The calibrated attempt started from the odometry's pair...
  EXPECT_TRUE(attempts[0]["chosen"]) << attempts.dump(2);
  EXPECT_EQ(attempts[0]["initialization"], "odometry_pair");
  EXPECT_EQ(attempts[0]["initial_pair"],
            json::array({ImageName(2), ImageName(11)}));
  EXPECT_EQ(attempts[0]["status"], "success");
  // ... after COLMAP's own search, recorded with the cause from its log.
  const json& first = attempts[1];
  EXPECT_EQ(first["initialization"], "colmap_search");
  EXPECT_FALSE(first["produced_model"]);
  EXPECT_NE(first["failure_cause"].get<std::string>().find(
                "No good initial image pair found"),
            std::string::npos)
      << attempts.dump(2);
}

// No verified pair, and COLMAP finds none: every rung tried, then exit 4
// naming them and the cause in COLMAP's log, not the intrinsics.
TEST_F(MapperInitialization, ExitFourNamesWhatWasTriedAndTheCause) {
  WriteImageFolder(8, "x");
  AddVerifiedPairs({});
  const std::string bin = WriteFakeColmapWithoutInitialPair();
  const CommandResult run =
      RunOdomcal(RunCommand({"--matcher", "sequential", "--force"}),
                 {{"PATH=" + bin + ":/usr/bin:/bin"}});
  ExpectColmapFailure(
      run,
      std::string(kRunError) +
          "COLMAP mapper produced no model in 4 runs (tried: COLMAP's "
          "initial pair search, relaxed initialisation tests) (see " +
          Path("ws/logs/mapper_seed_0.log") +
          "): no initial image pair passed COLMAP's tests (\"No good initial "
          "image pair found\")");
}

}  // namespace
}  // namespace odomcal::robustness_test
