// The on-robot log's file: its tables, the columns backfill added, its indexes, and the statements that write it.
// Written by RobotLog alone; sqlite3, tm-basecamp and the backfill reader read the file by these names.
#pragma once

#include <array>
#include <utility>

namespace tgw::log {

/// What was added since (forwarded_samples, link_rates, backfill's columns and log_id) is only added: a gateway
/// that predates it still writes such a file, so the version stays.
inline constexpr int SCHEMA_VERSION = 1;
inline constexpr const char* SCHEMA_SQL =
    "CREATE TABLE IF NOT EXISTS meta ("
    "  key TEXT PRIMARY KEY,"
    "  value TEXT NOT NULL);"
    "CREATE TABLE IF NOT EXISTS dropped_samples ("
    "  id INTEGER PRIMARY KEY,"
    "  topic TEXT NOT NULL,"
    "  type_name TEXT NOT NULL,"
    "  payload BLOB NOT NULL,"
    "  instance_key BLOB,"
    "  source_time_ns INTEGER NOT NULL,"
    "  arrival_ns INTEGER NOT NULL,"
    "  deadline_ns INTEGER NOT NULL,"
    "  logged_ns INTEGER NOT NULL,"
    "  reason TEXT NOT NULL);"  // and BACKFILL_COLUMNS, added by open()
    // Added after the first logs were written: IF NOT EXISTS gives an older file the table when it is reopened.
    "CREATE TABLE IF NOT EXISTS forwarded_samples ("
    "  id INTEGER PRIMARY KEY,"
    "  topic TEXT NOT NULL,"
    "  type_name TEXT NOT NULL,"
    "  instance_key BLOB,"
    "  source_time_ns INTEGER NOT NULL,"
    "  arrival_ns INTEGER NOT NULL,"
    "  deadline_ns INTEGER NOT NULL,"
    "  forwarded_ns INTEGER NOT NULL,"
    "  payload_bytes INTEGER NOT NULL);"
    // The link rate the gateway planned with, over time: where the robot's radio was weak, which the base camp
    // cannot hear (tm-basecamp linkmap).
    "CREATE TABLE IF NOT EXISTS link_rates ("
    "  id INTEGER PRIMARY KEY,"
    "  time_ns INTEGER NOT NULL,"
    "  sensed_bps REAL NOT NULL,"
    "  budget_bps REAL NOT NULL);";

/// The columns of dropped_samples that backfill added. open() adds those a file lacks with ALTER TABLE, to a new
/// file too, so that a new file and a migrated one have the same layout.
inline constexpr std::array<std::pair<const char*, const char*>, 4> BACKFILL_COLUMNS{{
    {"acked_ns", "INTEGER"},  // when the base camp acknowledged the row; NULL until it has it
    {"sends", "INTEGER NOT NULL DEFAULT 0"},
    {"last_sent_ns", "INTEGER"},
    // data, dispose or unregister. Only data is backfilled: a camp records no dispose live either, and without
    // the kind a dispose would read back as data without payload. Rows of older files were all taken as data.
    {"kind", "TEXT NOT NULL DEFAULT 'data'"},
}};

// Backfill's two questions, the unacknowledged rows by id and the acknowledged ones oldest first (at the cap), would
// otherwise scan the table, and read every payload on the way: the added columns stand after it in each record.
inline constexpr const char* BACKFILL_INDEX_SQL =
    "CREATE INDEX IF NOT EXISTS dropped_unacknowledged ON dropped_samples (id) WHERE acked_ns IS NULL;"
    "CREATE INDEX IF NOT EXISTS dropped_backfill_due ON dropped_samples (id) WHERE acked_ns IS NULL AND kind = 'data';"
    "CREATE INDEX IF NOT EXISTS dropped_acknowledged ON dropped_samples (id) WHERE acked_ns IS NOT NULL;";

// randomblob() draws from SQLite's generator, which the OS seeds (/dev/urandom). OR IGNORE: made once, then kept.
inline constexpr const char* LOG_ID_SQL =
    "INSERT OR IGNORE INTO meta (key, value) VALUES ('log_id', lower(hex(randomblob(16))));";

// The id is given, not left to SQLite: see next_dropped_id_.
inline constexpr const char* INSERT_SQL =
    "INSERT INTO dropped_samples (topic, type_name, payload, instance_key, source_time_ns, arrival_ns, "
    "deadline_ns, logged_ns, reason, id, kind) VALUES (?1, ?2, ?3, ?4, ?5, ?6, ?7, ?8, ?9, ?10, ?11);";

/// The largest id dropped_samples has given, that of a pruned row included: meta's max_dropped_id, which pruning
/// keeps, or the table's own.
inline constexpr const char* MAX_DROPPED_ID_SQL =
    "SELECT MAX(COALESCE((SELECT MAX(id) FROM dropped_samples), 0), "
    "COALESCE((SELECT CAST(value AS INTEGER) FROM meta WHERE key = 'max_dropped_id'), 0));";

inline constexpr const char* INSERT_FORWARDED_SQL =
    "INSERT INTO forwarded_samples (topic, type_name, instance_key, source_time_ns, arrival_ns, deadline_ns, "
    "forwarded_ns, payload_bytes) VALUES (?1, ?2, ?3, ?4, ?5, ?6, ?7, ?8);";

inline constexpr const char* INSERT_RATE_SQL =
    "INSERT INTO link_rates (time_ns, sensed_bps, budget_bps) VALUES (?1, ?2, ?3);";

inline constexpr const char* MARK_SENT_SQL =
    "UPDATE dropped_samples SET sends = sends + 1, last_sent_ns = ?2 WHERE id = ?1;";

// The first acknowledgement's time stays: a row acknowledged again (the camp's ack crossed a resend) is not new.
inline constexpr const char* MARK_ACKNOWLEDGED_SQL =
    "UPDATE dropped_samples SET acked_ns = ?3 WHERE id BETWEEN ?1 AND ?2 AND acked_ns IS NULL;";

/// What goes at the cap, in this order, with the meta counter of each.
struct PruneStage {
    const char* table;
    const char* condition;
    const char* meta_key;
};
inline constexpr std::array<PruneStage, 3> PRUNE_ORDER{{
    // The base camp has their payload, and they are the large rows.
    {"dropped_samples", "acked_ns IS NOT NULL", "pruned_acknowledged_rows"},
    // They only say that a sample left.
    {"forwarded_samples", "1", "pruned_forwarded_rows"},
    // Samples that are nowhere else: the last to go.
    {"dropped_samples", "acked_ns IS NULL", "pruned_dropped_rows"},
}};

}  // namespace tgw::log
