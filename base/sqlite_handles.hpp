#pragma once

#include <sqlite3.h>

#include <memory>

namespace tgw::base {

/// Owners of SQLite's connection and statement handles: the on-robot log's writer and reader, the base camp's
/// recordings and reports.
struct DbCloser {
    void operator()(sqlite3* db) const { sqlite3_close_v2(db); }
};
struct StmtFinalizer {
    void operator()(sqlite3_stmt* stmt) const { sqlite3_finalize(stmt); }
};
using DbPtr = std::unique_ptr<sqlite3, DbCloser>;
using StmtPtr = std::unique_ptr<sqlite3_stmt, StmtFinalizer>;

/// Prepares `sql` on `db` to be kept (SQLITE_PREPARE_PERSISTENT); null on failure, the message in `db`.
inline StmtPtr prepare_persistent(sqlite3* db, const char* sql) {
    sqlite3_stmt* raw = nullptr;
    if (sqlite3_prepare_v3(db, sql, -1, SQLITE_PREPARE_PERSISTENT, &raw, nullptr) != SQLITE_OK) {
        sqlite3_finalize(raw);
        return nullptr;
    }
    return StmtPtr(raw);
}

}  // namespace tgw::base
