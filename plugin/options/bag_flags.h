// The flags that choose what a robot bag gives odomcal (`odomcal extract`,
// `odomcal run --bag`): topics, which time stamps the messages, and the
// wheels of a JointState log; a table (option_table.h) bound to
// bag::BagExtractionOptions (adapters/bag/bag_extraction.h). Echoed in the
// result's `options.bag`.
#pragma once

#include "odomcal/adapters/bag/bag_extraction.h"
#include "odomcal/plugin/options/option_table.h"

namespace odomcal {

const OptionTable<bag::BagExtractionOptions>& BagTopicFlags();

}  // namespace odomcal
