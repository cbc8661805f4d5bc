// The real outputs of both result writers (`odomcal calibrate`'s
// CalibrationToJson, `odomcal colmap`/`run`'s ColmapCalibrationToJson) against
// docs/result_schema.json, with a small checker for the JSON Schema subset
// that file uses: type (a name or a list of names; "null" in the list makes a
// value nullable), required, properties, items, enum, minItems, maxItems and
// "$ref": "#/definitions/<name>". The checker is strict where a schema is
// not: a key the schema does not document is an error, so the documentation
// cannot fall behind the writers.

#include "odomcal/adapters/frame_selection.h"
#include "odomcal/plugin/cli/colmap_rig_outputs.h"
#include "odomcal/plugin/cli/rig_report.h"
#include "odomcal/plugin/options/project_flags.h"
#include "odomcal/plugin/options/run_flags.h"
#include "odomcal/plugin/report/calibration_report.h"
#include "odomcal/plugin/report/colmap_report.h"
#include "odomcal/plugin/report/report_testing.h"

#include <unistd.h>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

namespace odomcal {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

bool HasType(const json& value, const std::string& type) {
  if (type == "object") return value.is_object();
  if (type == "array") return value.is_array();
  if (type == "string") return value.is_string();
  if (type == "number") return value.is_number();
  if (type == "integer") return value.is_number_integer();
  if (type == "boolean") return value.is_boolean();
  if (type == "null") return value.is_null();
  ADD_FAILURE() << "unknown type in the schema: " << type;
  return false;
}

class SchemaChecker {
 public:
  explicit SchemaChecker(json root) : root_(std::move(root)) {}

  // One line per violation, each naming the JSON pointer of the value.
  std::vector<std::string> Check(const json& value) const {
    std::vector<std::string> errors;
    Check(value, root_, "", &errors);
    return errors;
  }

 private:
  const json& Resolve(const json& schema) const {
    if (!schema.contains("$ref")) return schema;
    const std::string ref = schema["$ref"];
    const std::string prefix = "#/definitions/";
    if (ref.rfind(prefix, 0) != 0 ||
        !root_["definitions"].contains(ref.substr(prefix.size()))) {
      throw std::runtime_error("unresolvable $ref " + ref);
    }
    return Resolve(root_["definitions"][ref.substr(prefix.size())]);
  }

  void Check(const json& value,
             const json& schema_or_ref,
             const std::string& where,
             std::vector<std::string>* errors) const {
    const json& schema = Resolve(schema_or_ref);
    const std::string at = where.empty() ? "/" : where;
    if (schema.contains("type")) {
      const json types = schema["type"].is_array()
                             ? schema["type"]
                             : json::array({schema["type"]});
      bool ok = false;
      for (const json& type : types)
        ok |= HasType(value, type.get<std::string>());
      if (!ok) {
        errors->push_back(at + ": " + std::string(value.type_name()) +
                          ", schema says " + types.dump());
        return;
      }
    }
    if (schema.contains("enum")) {
      bool found = false;
      for (const json& allowed : schema["enum"]) found |= allowed == value;
      if (!found)
        errors->push_back(at + ": " + value.dump() + " not in " +
                          schema["enum"].dump());
    }
    if (value.is_object()) {
      for (const json& key : schema.value("required", json::array())) {
        if (!value.contains(key.get<std::string>())) {
          errors->push_back(at + ": required key \"" + key.get<std::string>() +
                            "\" missing");
        }
      }
      const json properties = schema.value("properties", json::object());
      for (const auto& [key, item] : value.items()) {
        if (!properties.contains(key)) {
          errors->push_back(at + ": key \"" + key +
                            "\" not documented in the schema");
          continue;
        }
        Check(item, properties[key], where + "/" + key, errors);
      }
    }
    if (value.is_array()) {
      if (schema.contains("minItems") &&
          value.size() < schema["minItems"].get<size_t>()) {
        errors->push_back(at + ": fewer than " + schema["minItems"].dump() +
                          " items");
      }
      if (schema.contains("maxItems") &&
          value.size() > schema["maxItems"].get<size_t>()) {
        errors->push_back(at + ": more than " + schema["maxItems"].dump() +
                          " items");
      }
      if (schema.contains("items")) {
        for (size_t k = 0; k < value.size(); ++k) {
          Check(value[k],
                schema["items"],
                where + "/" + std::to_string(k),
                errors);
        }
      }
    }
  }

  json root_;
};

json ReadSchema() {
  std::ifstream file(ODOMCAL_RESULT_SCHEMA_PATH);
  EXPECT_TRUE(file.good()) << ODOMCAL_RESULT_SCHEMA_PATH;
  return json::parse(file);
}

std::string Lines(const std::vector<std::string>& errors) {
  std::string out;
  for (const std::string& error : errors) out += error + "\n";
  return out;
}

TEST(ResultSchema, IsDraft07AndDescribesEveryTopLevelKey) {
  const json schema = ReadSchema();
  EXPECT_EQ(schema["$schema"], "http://json-schema.org/draft-07/schema#");
  for (const auto& [key, property] : schema["properties"].items()) {
    EXPECT_TRUE(property.contains("description") || property.contains("$ref"))
        << key;
  }
}

TEST(ResultSchema, CalibrateOutputsConform) {
  const SchemaChecker checker(ReadSchema());
  const CalibrationRun success =
      SimulatedCalibrationRun(3, /*straight_only=*/false);
  ASSERT_TRUE(success.result.IsSuccess());
  const json out = CalibrationToJson(success.result, success.context);
  EXPECT_EQ(Lines(checker.Check(out)), "");
  EXPECT_FALSE(out.contains("colmap"));

  CalibrationRun partly = success;
  partly.result.observability.translation_y = Determination::kUndetermined;
  partly.result.observability.metric_scales[0] = Determination::kUndetermined;
  EXPECT_EQ(
      Lines(checker.Check(CalibrationToJson(partly.result, partly.context))),
      "");
  partly.result.observability = success.result.observability;
  partly.result.observability.rotation = Determination::kUndetermined;
  EXPECT_EQ(
      Lines(checker.Check(CalibrationToJson(partly.result, partly.context))),
      "");

  const CalibrationRun straight =
      SimulatedCalibrationRun(3, /*straight_only=*/true);
  ASSERT_FALSE(straight.result.IsSuccess());
  EXPECT_EQ(Lines(checker.Check(
                CalibrationToJson(straight.result, straight.context))),
            "");
}

// `calibrate --camera`: the reference camera's result with `cameras` and
// `camera_pairs`, for cameras calibrated and not.
TEST(ResultSchema, RigOutputConforms) {
  const SchemaChecker checker(ReadSchema());
  const CalibrationRun success =
      SimulatedCalibrationRun(3, /*straight_only=*/false);
  ASSERT_TRUE(success.result.IsSuccess());
  const CalibrationRun straight =
      SimulatedCalibrationRun(3, /*straight_only=*/true);
  RigCalibrationRun rig;
  for (const char* name : {"front", "rear", "left"}) {
    RigCameraRun camera;
    camera.name = name;
    camera.run = camera.name == "left" ? straight : success;
    camera.extrinsic = ExtrinsicOf(camera.run.result);
    rig.cameras.push_back(camera);
  }
  rig.cameras[1].run.result.odom_from_cam.translation.x() -= 0.5;
  rig.cameras[1].extrinsic = ExtrinsicOf(rig.cameras[1].run.result);
  rig.pairs.push_back(
      {0,
       1,
       CameraPairOf(*rig.cameras[0].extrinsic, *rig.cameras[1].extrinsic)});
  const json out = RigCalibrationToJson(rig);
  EXPECT_EQ(Lines(checker.Check(out)), "");
  EXPECT_EQ(out["cameras"].size(), 3u);
  EXPECT_EQ(out["camera_pairs"].size(), 1u);

  // A camera whose input the pipeline refused.
  rig.cameras[2].input_error = "no camera timestamp falls inside the odometry";
  rig.reference = 2;
  EXPECT_EQ(Lines(checker.Check(RigCalibrationToJson(rig))), "");
}

TEST(ResultSchema, ColmapOutputConforms) {
  const fs::path dir = fs::path(::testing::TempDir()) /
                       ("result_schema_test_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  SimulatedColmapProjectOptions options;
  options.fold = true;
  const ColmapCalibrationInputs inputs =
      WriteSimulatedColmapProject((dir / "project").string(), options);
  ColmapCalibrationRun run = CalibrateColmapProject(inputs);
  ASSERT_TRUE(run.check.result.IsSuccess()) << run.check.result.message;
  ASSERT_FALSE(run.check.stretches.empty());
  MapperAttempt with_model;
  with_model.produced_model = true;
  with_model.status = CalibrationStatus::kSuccess;
  run.mapper_attempts = {with_model,
                         MapperAttempt()};  // as `odomcal run` fills it
  run.chosen_mapper_attempt = 0;
  // The selected images: those registered, then a gap of 5 unregistered.
  std::vector<TimedImage> selected;
  for (size_t k = 0; k < run.segments[0].image_names.size(); ++k) {
    selected.push_back({run.segments[0].image_names[k],
                        run.segments[0].trajectory.poses[k].stamp_ns});
  }
  for (int k = 1; k <= 5; ++k) {
    selected.push_back(
        {"unregistered_" + std::to_string(k), selected.back().stamp_ns + k});
  }
  run.coverage = SummarizeImageCoverage(
      selected, RegisteredImages(run), ImagesInCalibration(run, 0));
  // The folded stretch the check rejected is a gap too.
  ASSERT_GE(run.coverage->stretches.size(), 2u);
  EXPECT_FALSE(run.coverage->stretches.back().in_calibration);
  const SchemaChecker checker(ReadSchema());
  // The library's default echo (ProjectFlagsEcho) is the schema's.
  const json out = ColmapCalibrationToJson(
      run, ProjectReportContext(inputs, run, "odomcal colmap"));
  EXPECT_EQ(Lines(checker.Check(out)), "");
  EXPECT_TRUE(out.contains("colmap"));
  // `odomcal run` adds its own flags, each choice's default the schema's,
  // with the frame spacing it used ("auto" resolved: numbers).
  json run_out = out;
  ReconstructionResult reconstruction;
  reconstruction.frame_spacing = AutomaticFrameSpacing(63.2);
  run_out["options"]["run"] = RunResultFlagsEcho(
      ReconstructionOptions(), reconstruction)["options"]["run"];
  EXPECT_EQ(Lines(checker.Check(run_out)), "");
  for (const std::string matcher : {"odometry", "spatial", "sequential"}) {
    run_out["options"]["run"]["matcher"] = matcher;
    EXPECT_EQ(Lines(checker.Check(run_out)), "") << matcher;
  }
  fs::remove_all(dir);
}

// `odomcal colmap` on several cameras (here two cameras of the same images)
// and `run --rig` with a camera COLMAP gave no model.
TEST(ResultSchema, ColmapRigOutputConforms) {
  const fs::path dir = fs::path(::testing::TempDir()) /
                       ("result_schema_rig_test_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  const ColmapCalibrationInputs inputs =
      WriteSimulatedColmapProject((dir / "project").string(), {});
  ColmapProjectCameras cameras;
  cameras.grouping = ColmapCameraGrouping::kBySubFolder;
  cameras.cameras = {{"front", {1}, 10}, {"rear", {1}, 10}};
  ColmapRigRun rig = CalibrateColmapRig(inputs, cameras, 1);
  ASSERT_EQ(rig.shared_scales.size(), 1u);
  const SchemaChecker checker(ReadSchema());
  const json echo = ProjectFlagsEcho(inputs);
  json out =
      ColmapRigToJson(rig, RigCalibrationOf(rig, "odomcal colmap", echo));
  EXPECT_EQ(Lines(checker.Check(out)), "");
  EXPECT_EQ(out["shared_scales"].size(), 1u);
  rig.cameras[0].run.reset();
  rig.cameras[0].input_error = "COLMAP mapper produced no model";
  rig.cameras[0].failure_status = "colmap_failed";
  out = ColmapRigToJson(rig, RigCalibrationOf(rig, "odomcal run", echo));
  EXPECT_EQ(Lines(checker.Check(out)), "");
  EXPECT_EQ(out["cameras"][0]["status"], "colmap_failed");
  EXPECT_TRUE(out["cameras"][0]["outputs"].is_null());
  fs::remove_all(dir);
}

TEST(ResultSchema, ColmapOutputWithScaleDriftConforms) {
  const fs::path dir = fs::path(::testing::TempDir()) /
                       ("result_schema_drift_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  SimulatedColmapProjectOptions options;
  options.scale_drift = 0.1;
  const ColmapCalibrationInputs inputs =
      WriteSimulatedColmapProject((dir / "project").string(), options);
  const ColmapCalibrationRun run = CalibrateColmapProject(inputs);
  ASSERT_FALSE(run.check.scale_drifts.empty());
  const json out = ColmapCalibrationToJson(
      run,
      ProjectReportContext(
          inputs, run, "odomcal colmap", ProjectFlagsEcho(inputs)));
  EXPECT_EQ(Lines(SchemaChecker(ReadSchema()).Check(out)), "");
  ASSERT_EQ(out["colmap"]["scale_drifts"].size(), 1u);
  EXPECT_EQ(out["colmap"]["scale_drifts"][0]["stretches"].size(),
            run.check.scale_drifts[0].stretches.size());
  fs::remove_all(dir);
}

// The checker itself finds what it is there to find.
TEST(ResultSchema,
     CheckerReportsWrongTypesMissingAndUndocumentedKeysAndBadEnums) {
  const SchemaChecker checker(ReadSchema());
  const CalibrationRun run =
      SimulatedCalibrationRun(3, /*straight_only=*/false);
  const json good = CalibrationToJson(run.result, run.context);

  json wrong_type = good;
  wrong_type["odom_from_cam"]["quaternion_wxyz"][0] = "1";
  EXPECT_EQ(
      Lines(checker.Check(wrong_type)),
      "/odom_from_cam/quaternion_wxyz/0: string, schema says [\"number\"]\n");
  json missing = good;
  missing.erase("status");
  EXPECT_EQ(Lines(checker.Check(missing)),
            "/: required key \"status\" missing\n");
  json undocumented = good;
  undocumented["diagnostics"]["new_key"] = 1;
  EXPECT_EQ(Lines(checker.Check(undocumented)),
            "/diagnostics: key \"new_key\" not documented in the schema\n");
  json bad_enum = good;
  bad_enum["status"] = "fine";
  EXPECT_EQ(
      Lines(checker.Check(bad_enum)).rfind("/status: \"fine\" not in [", 0),
      0u);
  json short_quaternion = good;
  short_quaternion["odom_from_cam"]["quaternion_wxyz"].erase(3);
  EXPECT_EQ(Lines(checker.Check(short_quaternion)),
            "/odom_from_cam/quaternion_wxyz: fewer than 4 items\n");
}

}  // namespace
}  // namespace odomcal
