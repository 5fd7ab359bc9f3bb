// A recording or an on-robot log opened for reading, as the base camp's reports read them.
#pragma once

#include <memory>
#include <string>

struct sqlite3;
struct sqlite3_stmt;

namespace tgw::basecamp {

using ReadOnlyDb = std::unique_ptr<sqlite3, int (*)(sqlite3*)>;
using Statement = std::unique_ptr<sqlite3_stmt, int (*)(sqlite3_stmt*)>;

/// Opens `path` read-only. Throws base::ConfigError "`who`: cannot open 'PATH': why" if it cannot.
ReadOnlyDb open_read_only(const std::string& path, const std::string& who);

/// Whether `table` has `column`: recordings and logs made before a column was added do not.
bool has_column(sqlite3* db, const std::string& table, const std::string& column);

/// Prepares `sql` on `db`. Throws base::ConfigError "`what`: why" if it cannot (a file of another kind).
Statement prepare(sqlite3* db, const char* sql, const std::string& what);

}  // namespace tgw::basecamp
