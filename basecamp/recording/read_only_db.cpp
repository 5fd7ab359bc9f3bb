#include "basecamp/recording/read_only_db.hpp"

#include <sqlite3.h>

#include "base/config_error.hpp"

namespace tgw::basecamp {

base::DbPtr open_read_only(const std::string& path, const std::string& who) {
    sqlite3* raw = nullptr;
    if (sqlite3_open_v2(path.c_str(), &raw, SQLITE_OPEN_READONLY, nullptr) != SQLITE_OK) {
        const std::string why = raw ? sqlite3_errmsg(raw) : "out of memory";
        sqlite3_close(raw);
        throw base::ConfigError(who + ": cannot open '" + path + "': " + why);
    }
    return base::DbPtr(raw);
}

bool has_column(sqlite3* db, const std::string& table, const std::string& column) {
    sqlite3_stmt* probe = nullptr;
    const std::string sql = "SELECT " + column + " FROM " + table + " LIMIT 0";
    const bool has = sqlite3_prepare_v2(db, sql.c_str(), -1, &probe, nullptr) == SQLITE_OK;
    sqlite3_finalize(probe);
    return has;
}

base::StmtPtr prepare(sqlite3* db, const char* sql, const std::string& what) {
    sqlite3_stmt* stmt = nullptr;
    if (sqlite3_prepare_v2(db, sql, -1, &stmt, nullptr) != SQLITE_OK)
        throw base::ConfigError(what + ": " + sqlite3_errmsg(db));
    return base::StmtPtr(stmt);
}

}  // namespace tgw::basecamp
