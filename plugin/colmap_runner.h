// Runs the COLMAP command-line program for odomcal: argv built directly (no
// shell), every command and its output kept in the workspace, exit codes
// checked and explained, finished stages reused when rerun with the same
// arguments.
//
// Workspace layout written here:
//   commands.txt          every command run, one per line, shell-quoted
//   logs/<stage>.log      stdout + stderr of the stage (glog to stderr)
//   stages/<stage>.done   the exact argv of a finished stage
//
// Stages form one chain: once a stage runs anew, every later stage of the
// same runner runs anew too, since its inputs may have changed.
#pragma once

#include <functional>
#include <stdexcept>
#include <string>
#include <vector>

namespace odomcal {

class ColmapError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

struct ColmapVersion {
  int major = 0;
  int minor = 0;
  int patch = 0;
  std::string banner;  // first line of `colmap help`
  bool AtLeast(int major_at_least, int minor_at_least) const;
};

// "COLMAP 3.8 -- Structure-from-Motion ..." -> 3.8.0; throws ColmapError.
ColmapVersion ParseColmapVersion(const std::string& banner);

// Option prefixes renamed in COLMAP 3.13: SiftExtraction -> FeatureExtraction,
// SiftMatching -> FeatureMatching.
std::string FeatureExtractionPrefix(const ColmapVersion& version);
std::string FeatureMatchingPrefix(const ColmapVersion& version);

// COLMAP's pixel thresholds suit megapixel images: two-view verification
// 4 px, the initial pair 4 px, registration 12 px, filtering 4 px. On
// 320x240 images they let the mapper now and then fold a stretch or register
// images degrees off (the `tilted` preset, seed 6: 1 of 3 runs with the
// defaults, 0 of 4 with 1.5 / 2 / 4 / 2 px), but stricter ones make mapping
// 2-4x slower, so `odomcal run` uses them only to match and map again.
struct ColmapPixelThresholds {
  double two_view_max_error_px = 4.0;
  double init_max_error_px = 4.0;
  double abs_pose_max_error_px = 12.0;
  double filter_max_reproj_error_px = 4.0;
};

// COLMAP's thresholds scaled by the image's larger side over 800 px, never
// above COLMAP's own: 1.6 / 1.6 / 4.8 / 1.6 px at 320x240. COLMAP's own when
// the size is unknown (<= 0).
ColmapPixelThresholds ScaledPixelThresholds(int image_max_side_px);

// The option holding the two-view threshold: SiftMatching.max_error up to
// 3.8, TwoViewGeometry.max_error from 3.9.
std::string TwoViewMaxErrorOption(const ColmapVersion& version);

// One argument shell-quoted for display in commands.txt and messages.
std::string ShellQuote(const std::string& argument);

struct ColmapStageResult {
  bool reused = false;  // finished earlier with the same argv; not rerun
  double seconds = 0.0;
  std::string log_path;
};

class ColmapRunner {
 public:
  struct Options {
    std::string executable = "colmap";  // looked up on PATH if no '/'
    std::string workspace;              // must exist
    bool reuse_finished_stages = true;
  };

  explicit ColmapRunner(Options options);

  // Runs `colmap help` once and parses its banner. Throws ColmapError when
  // COLMAP is missing or does not answer.
  const ColmapVersion& Version();

  // Runs `colmap <arguments...>` as stage `stage` (a file-name-safe word).
  // A stage is reused when stages/<stage>.done holds the same argv and every
  // path in `outputs` exists. Throws ColmapError naming the stage, the exit
  // code (134: COLMAP's CHECK failure / abort) and the log's last line.
  ColmapStageResult RunStage(const std::string& stage,
                             const std::vector<std::string>& arguments,
                             const std::vector<std::string>& outputs);

  // Whether RunStage with these arguments would reuse a finished stage.
  bool WillReuse(const std::string& stage,
                 const std::vector<std::string>& arguments,
                 const std::vector<std::string>& outputs) const;

  // No stage is reused from now on: the caller changed an input that the
  // stage markers do not record.
  void RunLaterStagesAnew() { reuse_allowed_ = false; }

 private:
  std::string CommandLine(const std::vector<std::string>& arguments) const;

  Options options_;
  bool reuse_allowed_ = true;  // false once a stage ran anew
  bool version_known_ = false;
  ColmapVersion version_;
};

}  // namespace odomcal
