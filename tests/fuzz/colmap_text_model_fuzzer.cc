// Fuzzes ReadColmapModel on a text model (cameras.txt, images.txt,
// points3D.txt). The input holds the three files in that order, split by
// SplitInput; each is written to a scratch folder, which is then read back.
//
// Expected outcome for malformed input: FormatError. Anything else (a crash,
// a sanitizer report, any other exception) escapes and is a finding.
#include "odomcal/adapters/colmap_model.h"
#include "odomcal/adapters/format_error.h"

#include "scratch_dir.h"
#include "split_input.h"

#include <cstddef>
#include <cstdint>

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static const odomcal::ScratchDir scratch;
  const auto files = odomcal::SplitInput<3>(odomcal::AsBytes(data, size));
  scratch.Write("cameras.txt", files[0]);
  scratch.Write("images.txt", files[1]);
  scratch.Write("points3D.txt", files[2]);
  try {
    odomcal::ReadColmapModel(scratch.path());
  } catch (const odomcal::FormatError&) {
  }
  return 0;
}
