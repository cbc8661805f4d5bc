#include "odomcal/solver/motion_pair.h"

#include <algorithm>

namespace odomcal {

int NumSegments(const MotionPairs& pairs) {
  int max_segment = -1;
  for (const MotionPair& pair : pairs) {
    max_segment = std::max(max_segment, pair.segment);
  }
  return max_segment + 1;
}

}  // namespace odomcal
