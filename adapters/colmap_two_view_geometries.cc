// One SELECT on two_view_geometries (colmap_two_view_geometries.h), each row
// range-checked as colmap_database.cc checks its tables.
#include "odomcal/adapters/colmap_two_view_geometries.h"

#include "odomcal/adapters/colmap_database_internal.h"

#include <sqlite3.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <string>
#include <tuple>

namespace odomcal {
namespace {

// COLMAP's kMaxNumImages: pair ids are image_id1 * this + image_id2.
constexpr uint64_t kMaxNumImages = 2147483647;

// 9 little-endian float64 (row-major) as a matrix; nothing for an empty,
// all-zero or non-finite blob.
std::optional<Eigen::Matrix3d> MatrixBlob(sqlite3_stmt* statement, int column) {
  if (sqlite3_column_type(statement, column) != SQLITE_BLOB ||
      sqlite3_column_bytes(statement, column) != 9 * 8) {
    return std::nullopt;
  }
  const auto* bytes =
      static_cast<const unsigned char*>(sqlite3_column_blob(statement, column));
  Eigen::Matrix3d matrix;
  for (int k = 0; k < 9; ++k) {
    uint64_t bits = 0;
    for (int b = 7; b >= 0; --b) bits = (bits << 8) | bytes[8 * k + b];
    double value = 0.0;
    std::memcpy(&value, &bits, sizeof(double));
    if (!std::isfinite(value)) return std::nullopt;
    matrix(k / 3, k % 3) = value;
  }
  if (matrix.isZero(0.0)) return std::nullopt;
  return matrix;
}

}  // namespace

uint64_t ColmapPairId(uint32_t image_id1, uint32_t image_id2) {
  if (image_id1 > image_id2) std::swap(image_id1, image_id2);
  return kMaxNumImages * image_id1 + image_id2;
}

std::vector<ColmapVerifiedPair> ReadColmapVerifiedPairs(
    const std::string& database_path, int min_inliers) {
  const internal::DatabaseHandle database =
      internal::OpenReadOnly(database_path);
  const internal::StatementHandle statement = internal::Prepare(
      database.get(),
      database_path,
      "SELECT pair_id, rows, config, E FROM two_view_geometries",
      "two_view_geometries");
  std::vector<ColmapVerifiedPair> pairs;
  while (internal::NextRow(database.get(), statement.get(), database_path)) {
    sqlite3_stmt* const row = statement.get();
    if (sqlite3_column_type(row, 0) != SQLITE_INTEGER ||
        sqlite3_column_type(row, 1) != SQLITE_INTEGER ||
        sqlite3_column_type(row, 2) != SQLITE_INTEGER) {
      internal::FailDatabase(database_path,
                             "two_view_geometries row " +
                                 std::to_string(pairs.size() + 1) +
                                 ": pair_id, rows or config is not an integer");
    }
    const int64_t pair_id = sqlite3_column_int64(row, 0);
    const int64_t rows = sqlite3_column_int64(row, 1);
    if (pair_id < 0 || rows < 0 || rows > (int64_t{1} << 30)) {
      internal::FailDatabase(
          database_path,
          "two_view_geometries pair_id " + std::to_string(pair_id) +
              ": pair_id or rows (" + std::to_string(rows) + ") out of range");
    }
    if (rows < min_inliers) continue;
    ColmapVerifiedPair pair;
    const uint64_t id = static_cast<uint64_t>(pair_id);
    pair.image_id2 = static_cast<uint32_t>(id % kMaxNumImages);
    pair.image_id1 =
        static_cast<uint32_t>((id - pair.image_id2) / kMaxNumImages);
    pair.num_inliers = static_cast<int>(rows);
    pair.config = static_cast<int>(sqlite3_column_int64(row, 2));
    pair.essential = MatrixBlob(row, 3);
    pairs.push_back(std::move(pair));
  }
  std::sort(pairs.begin(), pairs.end(), [](const auto& a, const auto& b) {
    return std::tie(a.image_id1, a.image_id2) <
           std::tie(b.image_id1, b.image_id2);
  });
  return pairs;
}

}  // namespace odomcal
