// Image ids in name order, for the database `odomcal run` creates.
//
// COLMAP's feature_extractor gives each image its id when its features are
// written, in the order its extraction threads finish: with two or more
// threads, the same images get other ids from run to run. The ids decide
// the order of COLMAP's later choices (the mapper's initial pair search and
// its ties), so a rerun of the same inputs mapped differently.
// RenumberColmapImagesByName gives the images ids 1..N in the order of
// their names (and, where the database has frames (COLMAP 3.12 and later),
// the frames ids in the order of their images), before anything refers to
// them: the images' keypoints, descriptors, position priors and frame data
// follow. Never for a user's project: only odomcal's own workspace database,
// right after feature extraction.
#pragma once

#include <string>

namespace odomcal {

// Renumbers as above inside one transaction; returns false when the ids
// were in name order already (nothing written). Throws FormatError naming
// the database when it cannot be opened or written, or when it holds
// matches already (their pair ids would need renumbering too).
bool RenumberColmapImagesByName(const std::string& database_path);

}  // namespace odomcal
