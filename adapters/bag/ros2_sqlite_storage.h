// rosbag2's SQLite storage (rosbag2_storage_sqlite3, .db3): tables topics(id,
// name, type, serialization_format, ...) and messages(id, topic_id,
// timestamp, data); internal: not installed.
#pragma once

#include "odomcal/adapters/bag/ros2_storage.h"

#include <memory>
#include <string>

namespace odomcal::bag::internal {

// Opens the file read-only (immutable: no lock, no journal) and reads its
// topics with their counts and time spans. Messages stream in timestamp
// order (ties by row id), as rosbag2 plays them. Throws FormatError
// ("path: ...") when the file is not such a database.
std::unique_ptr<Ros2Storage> OpenRos2SqliteStorage(const std::string& path);

// True when the file starts with SQLite's header "SQLite format 3\0".
bool LooksLikeSqliteFile(const std::string& path);

}  // namespace odomcal::bag::internal
