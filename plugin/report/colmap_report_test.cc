#include "odomcal/plugin/report/colmap_report.h"

#include "odomcal/plugin/report/colmap_calibration_outputs.h"
#include "odomcal/plugin/report/report_testing.h"

#include <unistd.h>

#include <gtest/gtest.h>

#include <cctype>
#include <cstdlib>
#include <filesystem>
#include <regex>
#include <string>
#include <vector>

namespace odomcal {
namespace {

namespace fs = std::filesystem;

bool Contains(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

// Each <tag ...>...</tag> (not nested in itself), in order. By hand:
// std::regex recurses per character and overflows the stack on an SVG.
std::vector<std::string> Elements(const std::string& html,
                                  const std::string& tag) {
  std::vector<std::string> elements;
  const std::string open = "<" + tag, close = "</" + tag + ">";
  for (size_t begin = html.find(open); begin != std::string::npos;
       begin = html.find(open, begin + 1)) {
    const char next = html[begin + open.size()];
    if (next != ' ' && next != '>') continue;  // e.g. <th> when looking for <t
    const size_t end = html.find(close, begin);
    if (end == std::string::npos) break;
    elements.push_back(html.substr(begin, end + close.size() - begin));
  }
  return elements;
}

std::string TextOf(const std::string& html) {
  return std::regex_replace(std::regex_replace(html, std::regex("<[^>]*>"), ""),
                            std::regex("^\\s+|\\s+$"),
                            "");
}

// One folder per process: ctest runs each test in its own process, in
// parallel.
fs::path ProcessDir() {
  return fs::path(::testing::TempDir()) /
         ("colmap_report_test_" + std::to_string(::getpid()));
}

// A real `odomcal colmap` run on a simulated project with a folded stretch,
// plus what only `odomcal run` fills in (mapper attempts) and a warning with
// markup characters.
class ColmapReport : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    const fs::path dir = ProcessDir();
    fs::remove_all(dir);
    SimulatedColmapProjectOptions options;
    options.fold = true;
    const ColmapCalibrationInputs inputs =
        WriteSimulatedColmapProject((dir / "project").string(), options);
    run_ = new ColmapCalibrationRun(CalibrateColmapProject(inputs));
    MapperAttempt first;
    first.random_seed = 1;
    first.produced_model = true;
    first.status = CalibrationStatus::kSuccess;
    first.num_sub_models = 1;
    first.num_registered_images = 400;
    first.num_pairs = 100;
    first.num_pairs_used = 90;
    first.num_contradicting_pairs = 10;
    MapperAttempt second = first;
    second.random_seed = 2;
    second.num_contradicting_pairs = 0;
    MapperAttempt none;
    none.matching_round = 1;
    run_->mapper_attempts = {first, second, none};
    run_->chosen_mapper_attempt = 1;
    run_->check.result.warnings.push_back(
        "a <b>bold</b> & \"quoted\" warning that goes on and on without a "
        "single space: " +
        std::string(300, 'x'));
    // As `odomcal run` fills it: the registered images and 4 more after.
    std::vector<TimedImage> selected;
    const ColmapSegment& segment = run_->segments[0];
    for (size_t k = 0; k < segment.image_names.size(); ++k) {
      selected.push_back(
          {segment.image_names[k], segment.trajectory.poses[k].stamp_ns});
    }
    for (int k = 1; k <= 4; ++k) {
      selected.push_back({"late_" + std::to_string(k),
                          segment.trajectory.poses.back().stamp_ns + k});
    }
    run_->coverage = SummarizeImageCoverage(
        selected, RegisteredImages(*run_), ImagesInCalibration(*run_, 0));
    context_ = new ReportContext(
        ProjectReportContext(inputs, *run_, "odomcal colmap"));
    html_ = new std::string(ColmapReportHtml(*run_, *context_));
    fs::create_directories(dir / "out");
    WriteColmapCalibrationOutputs(
        *run_, *context_, (dir / "out").string());  // for a look
  }
  static void TearDownTestSuite() {
    // ODOMCAL_KEEP_TEST_FILES keeps out/report.html
    // (scripts/report_screenshot.sh).
    if (std::getenv("ODOMCAL_KEEP_TEST_FILES") == nullptr) {
      fs::remove_all(ProcessDir());
    }
    delete run_;
    delete context_;
    delete html_;
  }
  static ColmapCalibrationRun* run_;
  static ReportContext* context_;
  static std::string* html_;
};
ColmapCalibrationRun* ColmapReport::run_ = nullptr;
ReportContext* ColmapReport::context_ = nullptr;
std::string* ColmapReport::html_ = nullptr;

TEST_F(ColmapReport, TheRunHasWhatTheReportShows) {
  ASSERT_TRUE(run_->check.result.IsSuccess()) << run_->check.result.message;
  ASSERT_FALSE(run_->check.stretches.empty());
  ASSERT_FALSE(run_->metric_models.empty());
}

TEST_F(ColmapReport, TagsAreBalanced) {
  std::vector<std::string> open;
  const std::string& html = *html_;
  // Tags scanned by hand: std::regex recurses per character of a tag and
  // overflows the stack on a long SVG path under AddressSanitizer.
  for (size_t begin = html.find('<'); begin != std::string::npos;
       begin = html.find('<', begin + 1)) {
    const size_t end = html.find('>', begin);
    ASSERT_NE(end, std::string::npos) << "unterminated tag at " << begin;
    const std::string tag = html.substr(begin + 1, end - begin - 1);
    const bool closing = !tag.empty() && tag[0] == '/';
    const size_t name_begin = closing ? 1 : 0;
    size_t name_end = name_begin;
    while (name_end < tag.size() &&
           std::isalnum(static_cast<unsigned char>(tag[name_end]))) {
      ++name_end;
    }
    if (name_end == name_begin) continue;  // <!DOCTYPE ...>, comments
    const std::string name = tag.substr(name_begin, name_end - name_begin);
    const bool self_closing = !tag.empty() && tag.back() == '/';
    if (self_closing || name == "meta" || name == "br") continue;
    if (!closing) {
      open.push_back(name);
      continue;
    }
    ASSERT_FALSE(open.empty()) << "</" << name << "> closes nothing";
    ASSERT_EQ(open.back(), name) << "at offset " << begin;
    open.pop_back();
  }
  EXPECT_TRUE(open.empty())
      << open.size() << " tags left open, first " << open.front();
  EXPECT_EQ(html.rfind("<!DOCTYPE html>", 0), 0u);
}

TEST_F(ColmapReport, EveryTableColumnIsHeadedAndEveryRowHasAllColumns) {
  const std::vector<std::string> tables = Elements(*html_, "table");
  ASSERT_EQ(tables.size(), 2u);  // the repeatability blocks, the mapper runs
  // Halves and quarters, each block a row.
  EXPECT_EQ(Elements(tables[0], "tr").size(), 1u + 2u + 4u);
  EXPECT_EQ(Elements(tables.back(), "tr").size(),
            1u + run_->mapper_attempts.size());
  EXPECT_EQ(Elements(Elements(tables.back(), "tr")[0], "th").size(), 10u);
  for (const std::string& table : tables) {
    const std::vector<std::string> rows = Elements(table, "tr");
    const std::vector<std::string> headers = Elements(rows[0], "th");
    for (const std::string& header : headers)
      EXPECT_FALSE(TextOf(header).empty()) << header;
    for (size_t r = 1; r < rows.size(); ++r) {
      EXPECT_TRUE(Elements(rows[r], "th").empty());
      const std::vector<std::string> cells = Elements(rows[r], "td");
      EXPECT_EQ(cells.size(), headers.size()) << rows[r];
      for (const std::string& cell : cells)
        EXPECT_FALSE(TextOf(cell).empty()) << rows[r];
    }
  }
  EXPECT_TRUE(Contains(*html_, "<td>yes</td></tr>"));  // the chosen attempt
}

TEST_F(ColmapReport, EveryFigureHasACaptionDefiningItsQuantities) {
  const std::vector<std::string> figures = Elements(*html_, "figure");
  ASSERT_EQ(figures.size(), 4u);
  for (const std::string& figure : figures) {
    EXPECT_EQ(Elements(figure, "svg").size(), 1u);
    const std::vector<std::string> captions = Elements(figure, "figcaption");
    ASSERT_EQ(captions.size(), 1u);
    EXPECT_GT(TextOf(captions[0]).size(), 100u) << captions[0];
  }
  // Each plotted quantity named in the caption of its figure.
  EXPECT_TRUE(
      Contains(figures[0], "Black square: the first odometry pose (start)"));
  EXPECT_TRUE(Contains(figures[0], "same scale"));
  for (const char* quantity : {"Rotation residual",
                               "translation residual",
                               "Odometry yaw change",
                               "motion pair"}) {
    EXPECT_TRUE(Contains(figures[1], quantity)) << quantity;
  }
  for (const char* quantity : {"Rotation angle difference</em> | |&theta;_cam| "
                               "&minus; |&theta;_odom| |",
                               "&theta;_cam is the angle the camera rotated",
                               "&theta;_odom the angle the robot",
                               "Step length ratio"}) {
    EXPECT_TRUE(Contains(figures[2], quantity)) << quantity;
  }
  for (const char* quantity : {"Each block's estimate",
                               "one standard deviation",
                               "the whole drive's estimate",
                               "Roll, pitch, yaw in degrees"}) {
    EXPECT_TRUE(Contains(figures[3], quantity)) << quantity;
  }
  EXPECT_FALSE(Contains(*html_, "angle A"));
}

// Used / not used and consistent / rejected are two meanings: two figures,
// two legends with titles, four colours.
TEST_F(ColmapReport, OneLegendPerMeaning) {
  const std::vector<std::string> svgs = Elements(*html_, "svg");
  ASSERT_EQ(svgs.size(), 4u);  // the last: the repeatability blocks
  auto labels = [](const std::string& svg) {
    std::vector<std::string> out;
    const std::regex label("class=\"legend-label\"[^>]*>([^<]*)<");
    for (std::sregex_iterator it(svg.begin(), svg.end(), label), end; it != end;
         ++it) {
      out.push_back((*it)[1]);
    }
    return out;
  };
  const std::vector<std::string> top = labels(svgs[0]);
  EXPECT_EQ(top.size(), 2u + run_->metric_models.size() + 1u);  // + start, end
  EXPECT_EQ(top[top.size() - 2], "start");
  EXPECT_EQ(top.back(), "end");
  EXPECT_EQ(
      labels(svgs[1]),
      (std::vector<std::string>{"used", "not used (outlier or left out)"}));
  EXPECT_TRUE(Contains(svgs[1], ">Pair in the calibration:<"));
  EXPECT_EQ(labels(svgs[2]),
            (std::vector<std::string>{
                "consistent", "in a stretch rejected as contradicting"}));
  EXPECT_TRUE(Contains(svgs[2], ">Pair according to the odometry:<"));
  for (const char* color : {"#2ca02c", "#d62728"}) {
    EXPECT_FALSE(Contains(svgs[1], color)) << color;
    EXPECT_TRUE(Contains(svgs[2], color)) << color;
  }
  // The rejected stretch is drawn: red markers exist.
  EXPECT_TRUE(Contains(svgs[2], "fill=\"#d62728\""));
}

TEST_F(ColmapReport, WarningsAppearVerbatimEscapedAndWrap) {
  EXPECT_TRUE(Contains(
      *html_,
      "<li class=\"warning\">a &lt;b&gt;bold&lt;/b&gt; &amp; "
      "&quot;quoted&quot; warning that goes on and on without a single "
      "space: " +
          std::string(300, 'x') + "</li>"));
  EXPECT_FALSE(Contains(*html_, "<b>bold"));
  for (const std::string& warning : run_->check.result.warnings) {
    if (warning[0] != 'a') {
      EXPECT_TRUE(Contains(*html_, ">" + warning + "</li>")) << warning;
    }
  }
  // Long lines wrap instead of being clipped or scrolled.
  EXPECT_TRUE(
      Contains(*html_,
               "pre{background:#f6f6f6;padding:1em;white-space:pre-wrap;"
               "overflow-wrap:anywhere}"));
  EXPECT_TRUE(Contains(*html_, "li,p,td,figcaption{overflow-wrap:anywhere}"));
  EXPECT_FALSE(Contains(*html_, "overflow-x"));
}

TEST_F(ColmapReport, JsonHasTheColmapSectionOfTheRun) {
  const nlohmann::json json = ColmapCalibrationToJson(*run_, *context_);
  EXPECT_EQ(json["schema"], "odomcal.calibration");
  EXPECT_EQ(json["status"], "success");
  const nlohmann::json& colmap = json["colmap"];
  ASSERT_EQ(colmap["sub_models"].size(), 1u);
  EXPECT_EQ(colmap["sub_models"][0]["name"], "0");
  EXPECT_TRUE(colmap["num_database_images"].is_null());  // no database given
  ASSERT_FALSE(colmap["inconsistent_stretches"].empty());
  for (const nlohmann::json& stretch : colmap["inconsistent_stretches"]) {
    EXPECT_EQ(stretch["segment"].is_null(), stretch["verdict"] == "rejected")
        << stretch;
  }
  ASSERT_EQ(colmap["mapper_attempts"].size(), 3u);
  EXPECT_TRUE(colmap["mapper_attempts"][1]["chosen"].get<bool>());
  EXPECT_TRUE(colmap["mapper_attempts"][2]["status"].is_null());  // no model
  EXPECT_EQ(json["warnings"].back(), run_->check.result.warnings.back());
  const ImageCoverage& coverage = *run_->coverage;
  EXPECT_DOUBLE_EQ(colmap["registered_fraction"].get<double>(),
                   coverage.Fraction());
  EXPECT_EQ(colmap["image_coverage"]["num_selected_images"],
            coverage.num_selected_images);
  EXPECT_EQ(colmap["image_coverage"]["stretches"].size(),
            coverage.stretches.size());
  EXPECT_FALSE(colmap["image_coverage"]["stretches"]
                   .back()["in_calibration"]
                   .get<bool>());
  EXPECT_NE(html_->find(CoverageClause(coverage)), std::string::npos);
}

}  // namespace
}  // namespace odomcal
