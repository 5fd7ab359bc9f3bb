// A recording or an on-robot log opened for reading, as the base camp's reports read them.
#pragma once

#include <string>

#include "base/sqlite_handles.hpp"

namespace tgw::basecamp {

/// Opens `path` read-only. Throws base::ConfigError "`who`: cannot open 'PATH': why" if it cannot.
base::DbPtr open_read_only(const std::string& path, const std::string& who);

/// Whether `table` has `column`: recordings and logs made before a column was added do not.
bool has_column(sqlite3* db, const std::string& table, const std::string& column);

/// Prepares `sql` on `db`. Throws base::ConfigError "`what`: why" if it cannot (a file of another kind).
base::StmtPtr prepare(sqlite3* db, const char* sql, const std::string& what);

}  // namespace tgw::basecamp
