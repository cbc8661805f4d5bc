// Progress of ReconstructAndCalibrate's stages to the caller's callback
// (reconstruction_pipeline.h). Internal: not installed.
#pragma once

#include "odomcal/plugin/colmap/colmap_progress.h"
#include "odomcal/plugin/colmap/colmap_runner.h"
#include "odomcal/plugin/colmap/reconstruction_pipeline.h"

#include <algorithm>
#include <chrono>
#include <optional>
#include <string>

namespace odomcal::reconstruction {

// Sends PipelineProgress to the caller's callback (if any), with a
// fraction that never decreases (stages 3 and 4 may run again), and, while a
// COLMAP stage runs, what COLMAP prints about its progress (at most once a
// second).
class Progress {
 public:
  explicit Progress(const ProgressCallback& callback) : callback_(callback) {}

  void Send(PipelineProgress::Event event,
            int stage,
            const std::string& message,
            double seconds = 0.0,
            double stage_fraction = 0.0) {
    PipelineProgress progress;
    progress.event = event;
    progress.stage = stage;
    progress.num_stages = kReconstructionStages;
    double done = stage;
    if (event == PipelineProgress::Event::kStageStarted) {
      done = stage - 1;
      live_stage_ = stage;
      live_ = ColmapOutputProgress(num_images_);
      live_start_ = std::chrono::steady_clock::now();
      live_sent_ = live_start_ - std::chrono::seconds(1);
    } else if (event == PipelineProgress::Event::kStageProgress) {
      done = stage - 1 + std::clamp(stage_fraction, 0.0, 1.0);
    }
    fraction_ = std::max(fraction_, done / kReconstructionStages);
    progress.fraction = fraction_;
    progress.message = message;
    progress.seconds = seconds;
    if (callback_) callback_(progress);
  }

  void Note(int stage, const std::string& message) {
    Send(PipelineProgress::Event::kNote, stage, message);
  }

  // The images COLMAP works on (the mapper's fraction).
  void SetNumImages(int num_images) { num_images_ = num_images; }

  // The current stage's COLMAP run started at `start` (before the stage's
  // title: a chunk mapped beside others): its elapsed time and time left
  // count from there.
  void SetLiveStart(std::chrono::steady_clock::time_point start) {
    live_start_ = std::min(live_start_, start);
  }

  // A line COLMAP printed during the current stage.
  void ColmapLine(const std::string& line) {
    if (!callback_ || !live_.Feed(line)) return;
    const auto now = std::chrono::steady_clock::now();
    if (now - live_sent_ < std::chrono::seconds(1)) return;
    live_sent_ = now;
    const double elapsed =
        std::chrono::duration<double>(now - live_start_).count();
    Send(PipelineProgress::Event::kStageProgress,
         live_stage_,
         live_.Describe(elapsed),
         elapsed,
         std::max(0.0, live_.Fraction()));
  }

 private:
  const ProgressCallback& callback_;
  double fraction_ = 0.0;
  int num_images_ = 0;
  int live_stage_ = 0;
  ColmapOutputProgress live_;
  std::chrono::steady_clock::time_point live_start_, live_sent_;
};

class StageClock {
 public:
  StageClock(Progress* progress, int index, const std::string& title)
      : progress_(progress), index_(index) {
    progress_->Send(PipelineProgress::Event::kStageStarted, index, title);
    start_ = std::chrono::steady_clock::now();
  }
  double Seconds() const {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() -
                                         start_)
        .count();
  }
  // `seconds`: the stage's own time when it ran beside others (a chunk's
  // mapper), instead of the time since this clock started.
  void Done(const std::string& note, std::optional<double> seconds = {}) {
    progress_->Send(PipelineProgress::Event::kStageFinished,
                    index_,
                    note,
                    seconds.value_or(Seconds()));
  }

 private:
  Progress* progress_;
  int index_;
  std::chrono::steady_clock::time_point start_;
};

inline std::string Note(const ColmapStageResult& stage) {
  return stage.reused ? "reused from an earlier run"
                      : "done, log " + stage.log_path;
}

}  // namespace odomcal::reconstruction
