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
// Stages form one chain: once a stage that ran anew has finished, every
// stage of the same runner started later runs anew too, since its inputs
// may have changed (stages started side by side do not depend on each
// other).
#pragma once

#include <chrono>
#include <functional>
#include <memory>
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
  std::string ToString() const;  // "4.1.1"
};

// "COLMAP 3.8 -- Structure-from-Motion ..." -> 3.8.0; throws ColmapError.
ColmapVersion ParseColmapVersion(const std::string& banner);

// The names, in the COLMAP `version` that runs, of the options odomcal
// passes whose names changed between 3.8 and 4.1 (read from COLMAP's
// option_manager.cc and exe/*.cc at every release tag;
// docs/colmap_versions.md). Every other option odomcal passes has one name in
// all of them.
// COLMAP refuses an unknown option (exit 1), so a wrong name fails the stage.
struct ColmapOptionNames {
  // feature_extractor: SiftExtraction.* until 3.12, FeatureExtraction.*
  // from 3.13 (only the device and thread options moved: the SIFT options,
  // max_num_features among them, keep SiftExtraction in every version).
  std::string extraction_use_gpu;
  std::string extraction_num_threads;
  std::string extraction_max_num_features;
  // The matchers and matches_importer: SiftMatching.* until 3.12,
  // FeatureMatching.* from 3.13.
  std::string matching_use_gpu;
  std::string matching_num_threads;
  // mapper: --image_list_path until 3.12, --Mapper.image_list_path from 3.13.
  std::string mapper_image_list_path;
  // The random seed: --random_seed until 3.12; from 3.13
  // --default_random_seed and --Mapper.random_seed (which also seeds each
  // RANSAC of the mapper), both given the seed.
  std::vector<std::string> mapper_random_seed;
};
ColmapOptionNames ColmapOptionNamesFor(const ColmapVersion& version);

// One argument shell-quoted for display in commands.txt and messages.
std::string ShellQuote(const std::string& argument);

struct ColmapStageResult {
  bool reused = false;  // finished earlier with the same argv; not rerun
  double seconds = 0.0;
  std::string log_path;
};

// Gets each line COLMAP prints while a stage runs (without its end of line).
using OutputLineCallback = std::function<void(const std::string& line)>;

class ColmapRunner;

// The program a stage runs: COLMAP itself, or the standalone GLOMAP (global
// structure from motion on a COLMAP database, for COLMAP versions before 4.0,
// which have no `global_mapper`).
enum class ColmapProgram { kColmap, kGlomap };

// A stage ColmapRunner::StartStage started: COLMAP running in the
// background (or the stage reused). Poll it while other work goes on, e.g.
// other stages, or Wait for it; destroying it while COLMAP runs stops COLMAP
// (SIGTERM) and waits for it to end. Not thread-safe: poll from one thread;
// the runner must outlive its stages.
class RunningStage {
 public:
  RunningStage(RunningStage&&) noexcept;
  RunningStage& operator=(RunningStage&&) noexcept;
  ~RunningStage();

  // The lines COLMAP printed since the last call go to `on_line` (without
  // a listener none are read, so a later one gets them all); true once the
  // stage ended.
  bool Poll(const OutputLineCallback& on_line = {});

  // Until the stage ends: polls every quarter second, or without a
  // listener just waits.
  void WaitForEnd(const OutputLineCallback& on_line = {});

  // The stage's own time once it ended (when COLMAP last wrote its log, if
  // nobody polled for a while); 0 for a reused stage.
  double seconds() const;
  std::chrono::steady_clock::time_point started() const;

  // Once Poll said the stage ended: marks it finished and returns its
  // result, or throws ColmapError as ColmapRunner::RunStage does.
  ColmapStageResult Finish();

  const std::string& stage() const;

 private:
  friend class ColmapRunner;
  struct State;
  explicit RunningStage(std::unique_ptr<State> state);
  bool Reap(const OutputLineCallback& on_line, int wait_options);
  void Stop() noexcept;
  std::unique_ptr<State> state_;
};

class ColmapRunner {
 public:
  struct Options {
    std::string executable = "colmap";         // looked up on PATH if no '/'
    std::string glomap_executable = "glomap";  // ColmapProgram::kGlomap
    std::string workspace;                     // must exist
    bool reuse_finished_stages = true;
    // Called from RunStage's thread, within a quarter second of COLMAP
    // writing the line to the stage's log; empty: the log is not followed.
    OutputLineCallback on_output_line;
  };

  explicit ColmapRunner(Options options);

  // Runs `colmap help` once and parses its banner. Throws ColmapError when
  // COLMAP is missing or does not answer.
  const ColmapVersion& Version();

  // Runs `colmap <arguments...>` as stage `stage` (a file-name-safe word).
  // A stage is reused when stages/<stage>.done holds the same argv, the
  // lists it names (--*_list_path) have the same content, and every path in
  // `outputs` exists. Throws ColmapError naming the stage, the exit
  // code (134: COLMAP's CHECK failure / abort) and the log's last line.
  ColmapStageResult RunStage(const std::string& stage,
                             const std::vector<std::string>& arguments,
                             const std::vector<std::string>& outputs,
                             ColmapProgram program = ColmapProgram::kColmap);

  // RunStage without waiting: COLMAP runs in the background while the
  // caller polls the returned stage (several stages may run side by side,
  // e.g. the mapper on independent chunks). Its failures, including a
  // missing COLMAP, are thrown by the stage's Finish().
  RunningStage StartStage(const std::string& stage,
                          const std::vector<std::string>& arguments,
                          const std::vector<std::string>& outputs,
                          ColmapProgram program = ColmapProgram::kColmap);

  // Whether RunStage with these arguments would reuse a finished stage.
  bool WillReuse(const std::string& stage,
                 const std::vector<std::string>& arguments,
                 const std::vector<std::string>& outputs,
                 ColmapProgram program = ColmapProgram::kColmap) const;

  const Options& options() const { return options_; }

  // No stage is reused from now on: the caller changed an input that the
  // stage markers do not record.
  void RunLaterStagesAnew() { reuse_allowed_ = false; }

 private:
  const std::string& Executable(ColmapProgram program) const;
  std::string CommandLine(const std::vector<std::string>& arguments,
                          ColmapProgram program) const;
  // What stages/<stage>.done records: the argv and the lists it names.
  std::string StageRecord(const std::vector<std::string>& arguments,
                          ColmapProgram program) const;

  Options options_;
  bool reuse_allowed_ = true;  // false once a stage ran anew
  bool version_known_ = false;
  ColmapVersion version_;
};

}  // namespace odomcal
