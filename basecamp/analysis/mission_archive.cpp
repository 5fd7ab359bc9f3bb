#include "basecamp/analysis/mission_archive.hpp"

#include <fcntl.h>
#include <sqlite3.h>
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <memory>
#include <set>
#include <system_error>
#include <tuple>
#include <utility>

#include "base/config_error.hpp"
#include "base/sqlite_handles.hpp"
#include "wire/receiver_report_topic.hpp"
#include "wire/status_topic.hpp"

namespace tgw::basecamp {

namespace {

namespace fs = std::filesystem;

constexpr int ARCHIVE_SCHEMA_VERSION = 1;
/// RTPS carries source times in 2^-32 s fractions and each hop rounds, so a recorded sample may be a nanosecond
/// or two off the time the gateway logged. Samples are paired on the exact time first, then within this.
constexpr std::int64_t SOURCE_TOLERANCE_NS = 1000;
/// SQLite virtual-machine steps between two looks at the stop flag, and rows between two in our own loops.
constexpr int PROGRESS_STEPS = 10000;
constexpr std::size_t ROWS_BETWEEN_STOP_CHECKS = 65536;

constexpr const char* ARCHIVE_SCHEMA = R"sql(
CREATE TABLE meta(
    key TEXT PRIMARY KEY,
    value TEXT NOT NULL);
CREATE TABLE mission_samples(
    id INTEGER PRIMARY KEY,
    topic TEXT NOT NULL,
    type_name TEXT NOT NULL,
    instance_key BLOB,
    source_ns INTEGER NOT NULL,
    payload_bytes INTEGER NOT NULL,
    payload BLOB,
    fate TEXT NOT NULL,
    reason TEXT,
    arrival_ns INTEGER,
    deadline_ns INTEGER,
    forwarded_ns INTEGER,
    logged_ns INTEGER,
    receive_ns INTEGER,
    latency_ns INTEGER,
    ttl_ns INTEGER,
    on_time INTEGER,
    robot_row INTEGER,
    basecamp_row INTEGER,
    backfilled INTEGER NOT NULL);
CREATE TEMP TABLE pairs(
    robot_row INTEGER,
    basecamp_row INTEGER);
)sql";

// One row per sample: the forwarded ones (received or lost, by the pairs), the dropped ones, and the recorded
// ones no robot row matched. The id follows an order of the inputs' own values, so a second merge numbers alike.
// ?1, ?2: the gateway's own topics, left out.
constexpr const char* FILL_ARCHIVE_SQL = R"sql(
INSERT INTO main.mission_samples
SELECT row_number() OVER (ORDER BY source_ns, topic, fate, robot_row, basecamp_row),
       topic, type_name, instance_key, source_ns, payload_bytes, payload, fate, reason, arrival_ns, deadline_ns,
       forwarded_ns, logged_ns, receive_ns, latency_ns, ttl_ns,
       CASE WHEN fate = 'received' AND ttl_ns IS NOT NULL THEN latency_ns <= ttl_ns END,
       robot_row, basecamp_row, backfilled
FROM (
    SELECT f.topic, f.type_name, f.instance_key, f.source_time_ns AS source_ns, f.payload_bytes, s.payload,
           CASE WHEN s.id IS NULL THEN 'lost' ELSE 'received' END AS fate, NULL AS reason, f.arrival_ns,
           f.deadline_ns, f.forwarded_ns, NULL AS logged_ns, s.receive_ns, s.receive_ns - f.source_time_ns AS latency_ns,
           COALESCE(s.lifespan_ns, t.lifespan_ns) AS ttl_ns, f.id AS robot_row, s.id AS basecamp_row,
           0 AS backfilled
    FROM temp.pairs p
    JOIN robot.forwarded_samples f ON f.id = p.robot_row
    LEFT JOIN recording.samples s ON s.id = p.basecamp_row
    LEFT JOIN recording.topics t ON t.topic = f.topic
    UNION ALL
    SELECT d.topic, d.type_name, d.instance_key, d.source_time_ns, length(d.payload), d.payload, 'dropped', d.reason,
           d.arrival_ns, d.deadline_ns, NULL, d.logged_ns, b.receive_ns, b.receive_ns - d.source_time_ns,
           t.lifespan_ns, d.id, b.id, b.id IS NOT NULL
    FROM robot.dropped_samples d
    LEFT JOIN temp.backfilled b ON b.row_id = d.id
    LEFT JOIN recording.topics t ON t.topic = d.topic
    WHERE d.topic NOT IN (?1, ?2)
    UNION ALL
    SELECT f.topic, f.type_name, f.instance, f.source_ns, length(f.payload), f.payload, 'dropped', f.drop_reason,
           NULL, NULL, NULL, NULL, f.receive_ns, f.receive_ns - f.source_ns, COALESCE(f.lifespan_ns, t.lifespan_ns),
           NULL, f.id, 1
    FROM temp.backfilled_freed f
    LEFT JOIN recording.topics t ON t.topic = f.topic
    WHERE f.topic NOT IN (?1, ?2)
    UNION ALL
    SELECT s.topic, s.type_name, s.instance, s.source_ns, length(s.payload), s.payload, 'received', NULL, NULL, NULL,
           NULL, NULL, s.receive_ns, s.receive_ns - s.source_ns, COALESCE(s.lifespan_ns, t.lifespan_ns), NULL, s.id, 0
    FROM temp.pairs p
    JOIN recording.samples s ON s.id = p.basecamp_row
    LEFT JOIN recording.topics t ON t.topic = s.topic
    WHERE p.robot_row IS NULL
);
)sql";

constexpr const char* COUNT_FATES_SQL =
    "SELECT topic, fate, reason, robot_row IS NULL, COUNT(*), COALESCE(SUM(on_time), 0), COUNT(ttl_ns), "
    "SUM(backfilled) FROM main.mission_samples GROUP BY 1, 2, 3, 4 ORDER BY 1, 2, 3, 4";

// The samples the camp's archive got from this log by backfill (docs/design/backfill.md), by the log's row; and
// those whose row the log no longer has: acknowledged, it was freed at the log's cap (--log-max-mib), and only the
// recording knows the sample now, its reason included. From a recording and a log that know backfill, else none.
constexpr const char* BACKFILLED_VIEW_SQL = R"sql(
CREATE TEMP VIEW backfilled AS
SELECT id, row_id, receive_ns FROM recording.samples
WHERE backfilled = 1 AND log_id = (SELECT value FROM robot.meta WHERE key = 'log_id');
CREATE TEMP VIEW backfilled_freed AS
SELECT s.id, s.topic, s.type_name, s.instance, s.source_ns, s.payload, s.receive_ns, s.lifespan_ns, s.drop_reason
FROM recording.samples s JOIN temp.backfilled b ON b.id = s.id
WHERE b.row_id NOT IN (SELECT id FROM robot.dropped_samples);
)sql";
constexpr const char* NO_BACKFILLED_VIEW_SQL = R"sql(
CREATE TEMP VIEW backfilled AS SELECT NULL AS id, NULL AS row_id, NULL AS receive_ns WHERE 0;
CREATE TEMP VIEW backfilled_freed AS
SELECT NULL AS id, NULL AS topic, NULL AS type_name, NULL AS instance, NULL AS source_ns, NULL AS payload,
       NULL AS receive_ns, NULL AS lifespan_ns, NULL AS drop_reason WHERE 0;
)sql";

/// A file as the error messages name it: "on-robot log 'robot.db'".
std::string named(const std::string& what, const std::string& path) {
    return what + " '" + path + "'";
}

/// A text column, "" for NULL.
std::string text_column(sqlite3_stmt* stmt, int column) {
    const auto* text = reinterpret_cast<const char*>(sqlite3_column_text(stmt, column));
    return text != nullptr ? text : "";
}

/// What pairs a forwarded robot row with a recorded sample.
struct Identity {
    std::int64_t row = 0;  ///< id in its own table
    std::uint32_t topic = 0;
    std::int64_t payload_bytes = 0;
    std::int64_t source_ns = 0;
    std::string instance;  ///< the key hash's bytes; empty when the topic is not keyed
};

/// The archive's rows before the payloads are copied: robot row and recorded sample, either may be missing.
struct Pair {
    std::optional<std::int64_t> robot_row;
    std::optional<std::int64_t> basecamp_row;
};

/// Walks two lists sorted by `before` (ties by row), pairing an element of each where `near` holds; the one that
/// sorts first otherwise has no partner in this pass and goes to its `_left` list.
template <typename Before, typename Near>
void pair_sorted(std::vector<Identity> robot, std::vector<Identity> basecamp, Before before, Near near,
                 std::vector<Pair>& pairs, std::vector<Identity>& robot_left, std::vector<Identity>& basecamp_left) {
    const auto by_row = [&](const Identity& a, const Identity& b) {
        return before(a, b) || (!before(b, a) && a.row < b.row);
    };
    std::sort(robot.begin(), robot.end(), by_row);
    std::sort(basecamp.begin(), basecamp.end(), by_row);
    std::size_t r = 0;
    std::size_t b = 0;
    while (r < robot.size() && b < basecamp.size()) {
        if (near(robot[r], basecamp[b])) {
            pairs.push_back({robot[r++].row, basecamp[b++].row});
        } else if (before(robot[r], basecamp[b])) {
            robot_left.push_back(std::move(robot[r++]));
        } else {
            basecamp_left.push_back(std::move(basecamp[b++]));
        }
    }
    std::move(robot.begin() + static_cast<std::ptrdiff_t>(r), robot.end(), std::back_inserter(robot_left));
    std::move(basecamp.begin() + static_cast<std::ptrdiff_t>(b), basecamp.end(), std::back_inserter(basecamp_left));
}

/// Pairs forwarded rows with recorded samples, duplicates by multiplicity: on the exact topic, payload size,
/// source time and instance first; then what is left on topic and payload size with the source time within
/// SOURCE_TOLERANCE_NS and any instance, for RTPS's rounding and for a publisher that sent no key hash (the
/// gateway then logs none, yet the recording may hold one). Every row of either list ends up in one Pair.
std::vector<Pair> match(std::vector<Identity> robot, std::vector<Identity> basecamp) {
    const auto exact = [](const Identity& a) { return std::tie(a.topic, a.payload_bytes, a.source_ns, a.instance); };
    const auto coarse = [](const Identity& a) { return std::tie(a.topic, a.payload_bytes, a.source_ns); };
    std::vector<Pair> pairs;
    std::vector<Identity> robot_left;
    std::vector<Identity> basecamp_left;
    pair_sorted(
        std::move(robot), std::move(basecamp),
        [&](const Identity& a, const Identity& b) { return exact(a) < exact(b); },
        [&](const Identity& a, const Identity& b) { return exact(a) == exact(b); }, pairs, robot_left, basecamp_left);

    std::vector<Identity> robot_lost;
    std::vector<Identity> basecamp_unmatched;
    pair_sorted(
        std::move(robot_left), std::move(basecamp_left),
        [&](const Identity& a, const Identity& b) { return coarse(a) < coarse(b); },
        [](const Identity& a, const Identity& b) {
            return a.topic == b.topic && a.payload_bytes == b.payload_bytes &&
                   std::llabs(a.source_ns - b.source_ns) <= SOURCE_TOLERANCE_NS;
        },
        pairs, robot_lost, basecamp_unmatched);
    for (const Identity& r : robot_lost)
        pairs.push_back({r.row, std::nullopt});
    for (const Identity& b : basecamp_unmatched)
        pairs.push_back({std::nullopt, b.row});
    return pairs;
}

/// A read-only URI for ATTACH: the path made absolute and percent-encoded, so no character of it reads as URI
/// syntax. Read-only, so a merge never changes an input, even one a gateway or recorder is still writing.
std::string read_only_uri(const std::string& path) {
    std::string uri = "file:";
    for (const unsigned char c : fs::absolute(path).string()) {
        const bool plain = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '/' ||
                           c == '.' || c == '-' || c == '_' || c == '~';
        if (plain) {
            uri += static_cast<char>(c);
        } else {
            char escaped[4];
            std::snprintf(escaped, sizeof(escaped), "%%%02X", c);
            uri += escaped;
        }
    }
    return uri + "?mode=ro";
}

int on_progress(void* stop) {
    return static_cast<const std::atomic<bool>*>(stop)->load() ? 1 : 0;
}

bool fsync_path(const std::string& path, int flags) {
    const int fd = ::open(path.c_str(), flags);
    if (fd < 0)
        return false;
    const bool ok = ::fsync(fd) == 0;
    ::close(fd);
    return ok;
}

void require_file(const std::string& what, const std::string& path) {
    std::error_code error;
    if (!fs::is_regular_file(path, error))
        throw base::ConfigError(named(what, path) + ": no such file");
}

/// An existing `out` is replaced only if it is a mission archive: never the recording or the log by a slip.
void require_replaceable(const std::string& out, const std::string& robot_log, const std::string& recording) {
    std::error_code error;
    if (!fs::exists(out, error))
        return;
    for (const std::string& input : {robot_log, recording}) {
        if (fs::equivalent(out, input, error))
            throw base::ConfigError(named("archive", out) + ": is an input of the merge");
    }
    sqlite3* raw = nullptr;
    const int rc = sqlite3_open_v2(out.c_str(), &raw, SQLITE_OPEN_READONLY, nullptr);
    base::DbPtr db(raw);
    sqlite3_stmt* stmt = nullptr;
    // The table's columns are not checked: a mission_samples table and the meta key are no accident.
    const bool archive = rc == SQLITE_OK &&
                         sqlite3_prepare_v2(db.get(),
                                            "SELECT value FROM meta WHERE key = 'archive_schema_version' "
                                            "AND (SELECT COUNT(*) FROM mission_samples WHERE 0) = 0",
                                            -1, &stmt, nullptr) == SQLITE_OK &&
                         sqlite3_step(stmt) == SQLITE_ROW;
    sqlite3_finalize(stmt);
    if (!archive)
        throw base::ConfigError(named("archive", out) + ": exists and is not a mission archive; not replacing it");
}

/// The archive being written: a temporary file next to `out`, removed unless commit() renamed it into place.
class TemporaryArchive {
  public:
    explicit TemporaryArchive(const std::string& out)
        : out_(out), path_(fs::absolute(out).string() + ".partial-" + std::to_string(::getpid())) {
        remove_file();
        sqlite3* raw = nullptr;
        // URI processing on, for the inputs' read-only ATTACH; the archive's own name is absolute, never a URI.
        const int rc =
            sqlite3_open_v2(path_.c_str(), &raw, SQLITE_OPEN_READWRITE | SQLITE_OPEN_CREATE | SQLITE_OPEN_URI, nullptr);
        db_.reset(raw);
        if (rc != SQLITE_OK)
            fail("cannot create " + path_);
        // Nothing to journal: until the rename, a failed or interrupted merge just deletes the file.
        exec("PRAGMA journal_mode=OFF; PRAGMA synchronous=OFF;", "cannot create " + path_);
    }

    ~TemporaryArchive() {
        db_.reset();
        if (!committed_)
            remove_file();
    }

    TemporaryArchive(const TemporaryArchive&) = delete;
    TemporaryArchive& operator=(const TemporaryArchive&) = delete;

    sqlite3* db() const { return db_.get(); }

    [[noreturn]] void fail(const std::string& what) const {
        throw base::ConfigError(named("archive", out_) + ": " + what + ": " + sqlite3_errmsg(db_.get()));
    }

    void exec(const char* sql, const std::string& what) const {
        if (sqlite3_exec(db_.get(), sql, nullptr, nullptr, nullptr) != SQLITE_OK)
            fail(what);
    }

    /// Closes the file, makes it durable and renames it over `out`: from here on, `out` is the new archive.
    void commit() {
        if (sqlite3_close(db_.get()) != SQLITE_OK)
            fail("cannot close " + path_);
        db_.release();
        if (!fsync_path(path_, O_RDONLY))
            throw base::ConfigError(named("archive", out_) + ": cannot sync " + path_);
        if (std::rename(path_.c_str(), out_.c_str()) != 0)
            throw base::ConfigError(named("archive", out_) + ": cannot rename " + path_ + " to it");
        committed_ = true;
        // The rename itself is durable once the directory is; a failure here leaves a whole archive either way.
        fsync_path(fs::absolute(out_).parent_path().string(), O_RDONLY | O_DIRECTORY);
    }

  private:
    void remove_file() const {
        std::error_code ignored;
        fs::remove(path_, ignored);
        fs::remove(path_ + "-journal", ignored);
    }

    std::string out_;
    std::string path_;
    base::DbPtr db_;
    bool committed_ = false;
};

/// Runs a merge on the temporary archive's connection, with both inputs attached read-only.
class Merger {
  public:
    Merger(TemporaryArchive& archive, const std::string& robot_log, const std::string& recording,
           const std::atomic<bool>* stop)
        : archive_(archive), db_(archive.db()), robot_log_(robot_log), recording_(recording), stop_(stop) {
        if (stop_ != nullptr)
            sqlite3_progress_handler(db_, PROGRESS_STEPS, on_progress, const_cast<std::atomic<bool>*>(stop_));
    }

    /// The counts, or nothing when stopped.
    std::optional<MergeCounts> run() {
        attach(robot_log_, "robot", "on-robot log");
        attach(recording_, "recording", "recording");
        require_columns("robot",
                        "SELECT id, topic, type_name, payload, instance_key, source_time_ns, arrival_ns, deadline_ns, "
                        "logged_ns, reason FROM robot.dropped_samples LIMIT 0",
                        named("on-robot log", robot_log_) + ": not an on-robot log of telemetry-gateway");
        require_columns("robot",
                        "SELECT id, topic, type_name, instance_key, source_time_ns, arrival_ns, deadline_ns, "
                        "forwarded_ns, payload_bytes FROM robot.forwarded_samples LIMIT 0",
                        named("on-robot log", robot_log_) +
                            ": has no forwarded samples (a gateway older than the mission archive wrote it), so "
                            "samples lost on the link cannot be told from samples never produced");
        require_columns("recording",
                        "SELECT id, topic, type_name, payload, source_ns, receive_ns, lifespan_ns, instance FROM "
                        "recording.samples LIMIT 0",
                        named("recording", recording_) + ": not a recording of tm-basecamp record or relay");
        require_columns("recording", "SELECT topic, lifespan_ns FROM recording.topics LIMIT 0",
                        named("recording", recording_) + ": not a recording of tm-basecamp record or relay");

        // One transaction: both inputs are read at one instant, even while a gateway or recorder still writes.
        archive_.exec("BEGIN;", "cannot start writing");
        archive_.exec(ARCHIVE_SCHEMA, "cannot create the tables");
        std::vector<Identity> robot;
        std::vector<Identity> basecamp;
        // Backfilled samples pair with the log's dropped rows, by row id, not with forwarded ones.
        const bool backfill =
            has_columns("SELECT backfilled, log_id, row_id, drop_reason FROM recording.samples LIMIT 0") &&
            has_columns("SELECT key, value FROM robot.meta LIMIT 0");
        archive_.exec(backfill ? BACKFILLED_VIEW_SQL : NO_BACKFILLED_VIEW_SQL, "cannot read the backfilled samples");
        if (!read_identities("SELECT id, topic, instance_key, source_time_ns, payload_bytes FROM "
                             "robot.forwarded_samples WHERE topic NOT IN (?1, ?2) ORDER BY id",
                             named("on-robot log", robot_log_), robot) ||
            !read_identities(backfill ? "SELECT id, topic, instance, source_ns, length(payload) FROM recording.samples "
                                        "WHERE topic NOT IN (?1, ?2) AND backfilled = 0 ORDER BY id"
                                      : "SELECT id, topic, instance, source_ns, length(payload) FROM recording.samples "
                                        "WHERE topic NOT IN (?1, ?2) ORDER BY id",
                             named("recording", recording_), basecamp))
            return std::nullopt;
        if (!write_pairs(match(std::move(robot), std::move(basecamp))))
            return std::nullopt;
        if (!fill_archive())
            return std::nullopt;
        copy_side_tables();
        MergeCounts counts = count_fates();
        write_meta();
        archive_.exec("DROP TABLE temp.pairs; DROP VIEW temp.backfilled; COMMIT;", "cannot commit");
        archive_.exec("DETACH DATABASE robot; DETACH DATABASE recording;", "cannot let go of the inputs");
        return counts;
    }

  private:
    bool stopped() const { return stop_ != nullptr && stop_->load(); }

    base::StmtPtr prepare(const char* sql, const std::string& who) const {
        sqlite3_stmt* raw = nullptr;
        if (sqlite3_prepare_v2(db_, sql, -1, &raw, nullptr) != SQLITE_OK)
            throw base::ConfigError(who + ": " + sqlite3_errmsg(db_));
        return base::StmtPtr(raw);
    }

    /// Binds the gateway's own topics, which the archive leaves out, to ?1 and ?2.
    static void bind_own_topics(sqlite3_stmt* stmt) {
        sqlite3_bind_text(stmt, 1, wire::STATUS_TOPIC, -1, SQLITE_STATIC);
        sqlite3_bind_text(stmt, 2, wire::RECEIVER_REPORT_TOPIC, -1, SQLITE_STATIC);
    }

    void attach(const std::string& path, const char* schema, const std::string& what) {
        const std::string sql = std::string("ATTACH DATABASE ?1 AS ") + schema;
        base::StmtPtr stmt = prepare(sql.c_str(), named(what, path));
        const std::string uri = read_only_uri(path);
        sqlite3_bind_text(stmt.get(), 1, uri.c_str(), -1, SQLITE_TRANSIENT);
        if (sqlite3_step(stmt.get()) != SQLITE_DONE)
            throw base::ConfigError(named(what, path) + ": cannot open: " + sqlite3_errmsg(db_));
    }

    /// Whether `probe` (a query of columns) compiles: what an older file lacks.
    bool has_columns(const char* probe) const {
        sqlite3_stmt* raw = nullptr;
        const bool ok = sqlite3_prepare_v2(db_, probe, -1, &raw, nullptr) == SQLITE_OK;
        sqlite3_finalize(raw);
        return ok;
    }

    /// Throws `message` with SQLite's reason ("file is not a database", "no such table") when `probe` fails.
    void require_columns(const char* schema, const char* probe, const std::string& message) const {
        sqlite3_stmt* raw = nullptr;
        if (sqlite3_prepare_v2(db_, probe, -1, &raw, nullptr) == SQLITE_OK) {
            sqlite3_finalize(raw);
            return;
        }
        throw base::ConfigError(message + " (" + schema + ": " + sqlite3_errmsg(db_) + ")");
    }

    /// Reads id, topic, instance, source time and payload size of every row `sql` selects; false when stopped.
    bool read_identities(const char* sql, const std::string& who, std::vector<Identity>& into) {
        base::StmtPtr stmt = prepare(sql, who);
        bind_own_topics(stmt.get());
        int rc = SQLITE_ROW;
        while ((rc = sqlite3_step(stmt.get())) == SQLITE_ROW) {
            Identity id;
            id.row = sqlite3_column_int64(stmt.get(), 0);
            id.topic = intern(text_column(stmt.get(), 1));
            const auto* key = static_cast<const char*>(sqlite3_column_blob(stmt.get(), 2));
            id.instance.assign(key != nullptr ? key : "",
                               static_cast<std::size_t>(sqlite3_column_bytes(stmt.get(), 2)));
            id.source_ns = sqlite3_column_int64(stmt.get(), 3);
            id.payload_bytes = sqlite3_column_int64(stmt.get(), 4);
            into.push_back(std::move(id));
            if (into.size() % ROWS_BETWEEN_STOP_CHECKS == 0 && stopped())
                return false;
        }
        if (rc == SQLITE_INTERRUPT || stopped())
            return false;
        if (rc != SQLITE_DONE)
            throw base::ConfigError(who + ": cannot read: " + sqlite3_errmsg(db_));
        return true;
    }

    std::uint32_t intern(const std::string& topic) {
        return topics_.emplace(topic, static_cast<std::uint32_t>(topics_.size())).first->second;
    }

    bool write_pairs(const std::vector<Pair>& pairs) {
        base::StmtPtr insert = prepare("INSERT INTO temp.pairs (robot_row, basecamp_row) VALUES (?1, ?2)", "archive");
        std::size_t written = 0;
        for (const Pair& p : pairs) {
            if (p.robot_row)
                sqlite3_bind_int64(insert.get(), 1, *p.robot_row);
            else
                sqlite3_bind_null(insert.get(), 1);
            if (p.basecamp_row)
                sqlite3_bind_int64(insert.get(), 2, *p.basecamp_row);
            else
                sqlite3_bind_null(insert.get(), 2);
            const int rc = sqlite3_step(insert.get());
            sqlite3_reset(insert.get());
            if (rc == SQLITE_INTERRUPT || (++written % ROWS_BETWEEN_STOP_CHECKS == 0 && stopped()))
                return false;
            if (rc != SQLITE_DONE)
                archive_.fail("cannot write");
        }
        return true;
    }

    bool fill_archive() {
        base::StmtPtr fill = prepare(FILL_ARCHIVE_SQL, "archive");
        bind_own_topics(fill.get());
        const int rc = sqlite3_step(fill.get());
        if (rc == SQLITE_INTERRUPT || stopped())
            return false;
        if (rc != SQLITE_DONE)
            throw base::ConfigError("cannot merge " + named("on-robot log", robot_log_) + " and " +
                                    named("recording", recording_) + ": " + sqlite3_errmsg(db_));
        return true;
    }

    /// What the inputs know besides samples, copied when they have it (older files do not): the gateway's link rate
    /// over time (for linkmap) and the IDL of types known from their publishers' TypeObjects (for export's schemas).
    void copy_side_tables() {
        archive_.exec(
            "CREATE TABLE link_rates(time_ns INTEGER NOT NULL, sensed_bps REAL NOT NULL, budget_bps REAL "
            "NOT NULL); CREATE TABLE announced_types(type_name TEXT PRIMARY KEY, idl TEXT NOT NULL);",
            "cannot create the tables");
        if (has_table("robot", "link_rates"))
            archive_.exec(
                "INSERT INTO main.link_rates SELECT time_ns, sensed_bps, budget_bps FROM robot.link_rates "
                "ORDER BY time_ns, id;",
                "cannot copy the link rates");
        if (has_table("recording", "announced_types"))
            archive_.exec(
                "INSERT INTO main.announced_types SELECT type_name, idl FROM recording.announced_types "
                "ORDER BY type_name;",
                "cannot copy the announced types");
    }

    bool has_table(const std::string& schema, const char* table) const {
        const std::string sql = "SELECT 1 FROM " + schema + ".sqlite_master WHERE type = 'table' AND name = ?1";
        base::StmtPtr stmt = prepare(sql.c_str(), schema);
        sqlite3_bind_text(stmt.get(), 1, table, -1, SQLITE_STATIC);
        return sqlite3_step(stmt.get()) == SQLITE_ROW;
    }

    MergeCounts count_fates() {
        base::StmtPtr stmt = prepare(COUNT_FATES_SQL, "archive");
        std::map<std::string, TopicFates> by_topic;
        std::set<std::string> ttl_known;
        while (sqlite3_step(stmt.get()) == SQLITE_ROW) {
            const std::string name = text_column(stmt.get(), 0);
            const std::string fate = text_column(stmt.get(), 1);
            const bool no_robot_row = sqlite3_column_int(stmt.get(), 3) != 0;
            const auto n = static_cast<std::uint64_t>(sqlite3_column_int64(stmt.get(), 4));
            TopicFates& t = by_topic[name];
            t.topic = name;
            if (sqlite3_column_int64(stmt.get(), 6) > 0)
                ttl_known.insert(name);
            if (fate == "received") {
                t.received += n;
                t.on_time = t.on_time.value_or(0) + static_cast<std::uint64_t>(sqlite3_column_int64(stmt.get(), 5));
                if (no_robot_row)
                    t.received_unmatched += n;
            } else if (fate == "lost") {
                t.lost += n;
            } else {
                t.backfilled += static_cast<std::uint64_t>(sqlite3_column_int64(stmt.get(), 7));
                const std::string why = text_column(stmt.get(), 2);
                const auto known = std::find(core::DROP_REASON_NAMES.begin(), core::DROP_REASON_NAMES.end(), why);
                if (known != core::DROP_REASON_NAMES.end())
                    t.dropped[static_cast<std::size_t>(known - core::DROP_REASON_NAMES.begin())] += n;
                else
                    t.dropped_other += n;
            }
        }
        MergeCounts counts;
        counts.total.topic = "total";
        for (auto& [name, t] : by_topic) {
            if (ttl_known.count(name) == 0)
                t.on_time.reset();
            else if (!t.on_time)
                t.on_time = 0;
            counts.total.received += t.received;
            counts.total.received_unmatched += t.received_unmatched;
            if (t.on_time)
                counts.total.on_time = counts.total.on_time.value_or(0) + *t.on_time;
            for (std::size_t i = 0; i < core::DROP_REASON_COUNT; ++i)
                counts.total.dropped[i] += t.dropped[i];
            counts.total.dropped_other += t.dropped_other;
            counts.total.lost += t.lost;
            counts.total.backfilled += t.backfilled;
            counts.topics.push_back(std::move(t));
        }
        return counts;
    }

    void write_meta() {
        base::StmtPtr insert = prepare("INSERT INTO main.meta (key, value) VALUES (?1, ?2)", "archive");
        const std::vector<std::pair<std::string, std::string>> rows = {
            {"archive_schema_version", std::to_string(ARCHIVE_SCHEMA_VERSION)},
            {"robot_log", robot_log_},
            {"recording", recording_},
        };
        for (const auto& [key, value] : rows) {
            sqlite3_bind_text(insert.get(), 1, key.c_str(), -1, SQLITE_TRANSIENT);
            sqlite3_bind_text(insert.get(), 2, value.c_str(), -1, SQLITE_TRANSIENT);
            if (sqlite3_step(insert.get()) != SQLITE_DONE)
                archive_.fail("cannot write the meta table");
            sqlite3_reset(insert.get());
        }
    }

    TemporaryArchive& archive_;
    sqlite3* db_;
    const std::string& robot_log_;
    const std::string& recording_;
    const std::atomic<bool>* stop_;
    std::map<std::string, std::uint32_t> topics_;
};

}  // namespace

std::uint64_t TopicFates::dropped_total() const {
    std::uint64_t total = dropped_other;
    for (const std::uint64_t n : dropped)
        total += n;
    return total;
}

std::uint64_t TopicFates::produced() const {
    return received + dropped_total() + lost;
}

std::optional<MergeCounts> merge_mission(const std::string& robot_log, const std::string& recording,
                                         const std::string& out, const std::atomic<bool>* stop) {
    require_file("on-robot log", robot_log);
    require_file("recording", recording);
    require_replaceable(out, robot_log, recording);
    TemporaryArchive archive(out);
    std::optional<MergeCounts> counts = Merger(archive, robot_log, recording, stop).run();
    if (!counts || (stop != nullptr && stop->load()))
        return std::nullopt;  // the temporary archive goes with `archive`; `out` is as it was
    archive.commit();
    return counts;
}

}  // namespace tgw::basecamp
