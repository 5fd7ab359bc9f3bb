#include "basecamp/analysis/grant_summary.hpp"

#include <sqlite3.h>

#include <cstdio>
#include <memory>

#include "base/config_error.hpp"
#include "base/sqlite_handles.hpp"
#include "basecamp/recording/read_only_db.hpp"

namespace tgw::basecamp {

namespace {

std::string cannot_read(const std::string& path) {
    return path + ": cannot read its grants";
}

bool has_table(sqlite3* db, const std::string& path, const char* table) {
    base::StmtPtr stmt =
        prepare(db, "SELECT 1 FROM sqlite_master WHERE type = 'table' AND name = ?1", cannot_read(path));
    sqlite3_bind_text(stmt.get(), 1, table, -1, SQLITE_STATIC);
    return sqlite3_step(stmt.get()) == SQLITE_ROW;
}

}  // namespace

std::optional<GrantSummary> read_grant_summary(const std::string& path) {
    const base::DbPtr owned = open_read_only(path, "report");
    sqlite3* db = owned.get();
    if (!has_table(db, path, "channel") || !has_table(db, path, "grants"))
        return std::nullopt;
    GrantSummary summary;
    base::StmtPtr channel = prepare(db,
                                    "SELECT COUNT(*), MIN(channel_bps), AVG(channel_bps), MAX(channel_bps), "
                                    "COUNT(verdict) FROM channel",
                                    cannot_read(path));
    if (sqlite3_step(channel.get()) != SQLITE_ROW || sqlite3_column_int64(channel.get(), 0) == 0)
        return std::nullopt;
    summary.rounds = static_cast<std::uint64_t>(sqlite3_column_int64(channel.get(), 0));
    summary.min_channel_bps = sqlite3_column_double(channel.get(), 1);
    summary.mean_channel_bps = sqlite3_column_double(channel.get(), 2);
    summary.max_channel_bps = sqlite3_column_double(channel.get(), 3);
    summary.measured = sqlite3_column_int64(channel.get(), 4) > 0;
    // A robot restarted has two gateways: its name holds both. The last grant is its newest round's.
    base::StmtPtr robots =
        prepare(db,
                "SELECT COALESCE(robot, gateway) AS who, COUNT(*), MIN(rate_bps), AVG(rate_bps), "
                "MAX(rate_bps), (SELECT g2.rate_bps FROM grants g2 WHERE COALESCE(g2.robot, g2.gateway) = "
                "COALESCE(g.robot, g.gateway) ORDER BY g2.time_ns DESC LIMIT 1) "
                "FROM grants g GROUP BY who ORDER BY who",
                cannot_read(path));
    while (sqlite3_step(robots.get()) == SQLITE_ROW) {
        RobotGrants r;
        r.robot = reinterpret_cast<const char*>(sqlite3_column_text(robots.get(), 0));
        r.rounds = static_cast<std::uint64_t>(sqlite3_column_int64(robots.get(), 1));
        r.min_bps = sqlite3_column_double(robots.get(), 2);
        r.mean_bps = sqlite3_column_double(robots.get(), 3);
        r.max_bps = sqlite3_column_double(robots.get(), 4);
        r.last_bps = sqlite3_column_double(robots.get(), 5);
        summary.robots.push_back(std::move(r));
    }
    return summary;
}

void print_grant_summary(std::ostream& out, const GrantSummary& summary) {
    char line[256];
    std::snprintf(line, sizeof(line),
                  "\nchannel shared by grants (%s): %llu rounds, %.0f bit/s on average (%.0f to %.0f)\n",
                  summary.measured ? "measured" : "--channel-rate", static_cast<unsigned long long>(summary.rounds),
                  summary.mean_channel_bps, summary.min_channel_bps, summary.max_channel_bps);
    out << line;
    std::snprintf(line, sizeof(line), "%-20s %8s %10s %10s %10s %10s\n", "robot", "rounds", "min_bps", "mean_bps",
                  "max_bps", "last_bps");
    out << line;
    for (const RobotGrants& r : summary.robots) {
        std::snprintf(line, sizeof(line), "%-20s %8llu %10.0f %10.0f %10.0f %10.0f\n", r.robot.c_str(),
                      static_cast<unsigned long long>(r.rounds), r.min_bps, r.mean_bps, r.max_bps, r.last_bps);
        out << line;
    }
}

}  // namespace tgw::basecamp
