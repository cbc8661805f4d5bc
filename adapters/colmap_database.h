// Read-only access to a COLMAP project database (database.db, SQLite).
//
// Only the `images` (image_id, name, camera_id) and `cameras` (camera_id,
// model, width, height, params, prior_focal_length) columns are read; their
// names and meaning are the same from COLMAP 3.8 (whose images table also
// holds prior_q*/prior_t*) to 4.1, so databases of any of these versions work
// (colmap_database_version.h tells the versions apart). Camera model ids are
// those of colmap_model.h: 0 to 17, as COLMAP 4.1 knows them.
// image_ids are assigned in import order, NOT in name order: join images
// across the database and models by name.
//
// The database is opened with SQLITE_OPEN_READONLY through a URI with
// `mode=ro&immutable=1`: SQLite then takes no locks and creates no journal,
// -wal or -shm file, so the user's project stays byte-identical. The price of
// immutable=1: a database that another process (a running COLMAP) is writing
// at the same time may be read inconsistently, and changes still sitting in
// a -wal file are not seen. COLMAP closes its databases cleanly, so finished
// projects are read correctly.
//
// Errors throw FormatError naming the database path: missing file, not an
// SQLite database, no COLMAP tables, unknown camera model ids, a params blob
// whose size is not 8 * ColmapCameraModelNumParams(model), non-finite
// params, ids outside COLMAP's uint32 range.
#pragma once

#include "odomcal/adapters/colmap_model.h"

#include <cstdint>
#include <string>
#include <vector>

namespace odomcal {

struct ColmapDatabaseImage {
  uint32_t image_id = 0;
  std::string name;  // relative to the image folder, '/'-separated
  uint32_t camera_id = 0;
};

struct ColmapDatabaseCamera {
  // params decoded from the blob of little-endian float64 values.
  ColmapCamera camera;
  // True when the focal length came from EXIF or the user (COLMAP's
  // prior_focal_length column), false when it was guessed from the image
  // size.
  bool prior_focal_length = false;
};

// All rows of the images table, sorted by image_id.
std::vector<ColmapDatabaseImage> ReadColmapDatabaseImages(
    const std::string& database_path);

// All rows of the cameras table, sorted by camera_id.
std::vector<ColmapDatabaseCamera> ReadColmapDatabaseCameras(
    const std::string& database_path);

}  // namespace odomcal
