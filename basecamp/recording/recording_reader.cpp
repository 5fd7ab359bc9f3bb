#include "basecamp/recording/recording_reader.hpp"

#include <sqlite3.h>

#include <memory>

#include "base/config_error.hpp"
#include "base/sqlite_handles.hpp"
#include "basecamp/recording/read_only_db.hpp"

namespace tgw::basecamp {

namespace {

std::string text_column(sqlite3_stmt* stmt, int column) {
    const auto* text = sqlite3_column_text(stmt, column);
    return text ? reinterpret_cast<const char*>(text) : std::string();
}

std::optional<std::int64_t> optional_column(sqlite3_stmt* stmt, int column) {
    if (sqlite3_column_type(stmt, column) == SQLITE_NULL)
        return std::nullopt;
    return sqlite3_column_int64(stmt, column);
}

std::vector<std::uint8_t> blob_column(sqlite3_stmt* stmt, int column) {
    const auto* data = static_cast<const std::uint8_t*>(sqlite3_column_blob(stmt, column));
    return std::vector<std::uint8_t>(data, data + sqlite3_column_bytes(stmt, column));
}

bool has_table(sqlite3* db, const char* name) {
    sqlite3_stmt* raw = nullptr;
    sqlite3_prepare_v2(db, "SELECT 1 FROM sqlite_master WHERE type='table' AND name=?", -1, &raw, nullptr);
    base::StmtPtr stmt(raw);
    sqlite3_bind_text(raw, 1, name, -1, SQLITE_STATIC);
    return sqlite3_step(raw) == SQLITE_ROW;
}

}  // namespace

RecordingReader::RecordingReader(const std::string& path, const std::string& flag) : path_(path), flag_(flag) {
    sqlite3* raw = nullptr;
    const int opened = sqlite3_open_v2(path.c_str(), &raw, SQLITE_OPEN_READONLY, nullptr);
    db_.reset(raw);
    if (opened != SQLITE_OK) {
        const std::string why = raw ? sqlite3_errmsg(raw) : "out of memory";
        throw base::ConfigError(flag + ": cannot open '" + path + "': " + why);
    }
    archive_ = has_table(db_.get(), "mission_samples");
    if (!archive_ && (!has_table(db_.get(), "topics") || !has_table(db_.get(), "samples"))) {
        throw base::ConfigError(flag + ": '" + path +
                                "' is not a recording of tm-basecamp record (no topics and samples tables) nor a "
                                "mission archive of merge");
    }
}

std::vector<std::pair<std::int64_t, double>> RecordingReader::link_rates() const {
    std::vector<std::pair<std::int64_t, double>> rates;
    if (!archive_ || !has_table(db_.get(), "link_rates"))
        return rates;
    sqlite3_stmt* raw = nullptr;
    sqlite3_prepare_v2(db_.get(), "SELECT time_ns, sensed_bps FROM link_rates ORDER BY time_ns", -1, &raw, nullptr);
    base::StmtPtr rows(raw);
    while (sqlite3_step(raw) == SQLITE_ROW)
        rates.emplace_back(sqlite3_column_int64(raw, 0), sqlite3_column_double(raw, 1));
    return rates;
}

std::uint64_t RecordingReader::read(SampleConsumer& into) {
    return archive_ ? read_archive(into) : read_recording(into);
}

std::uint64_t RecordingReader::read_archive(SampleConsumer& into) {
    sqlite3_stmt* raw = nullptr;
    // A backfilled sample takes its place in the mission at its source time (archives made before backfill have
    // none).
    const std::string backfilled = has_column(db_.get(), "mission_samples", "backfilled") ? "backfilled" : "0";
    const std::string select =
        "SELECT topic, type_name, payload, source_ns, fate, reason, receive_ns, logged_ns, forwarded_ns, ttl_ns, "
        "instance_key, " +
        backfilled + " AS backfilled FROM mission_samples ORDER BY COALESCE(CASE WHEN " + backfilled +
        " THEN source_ns END, receive_ns, logged_ns, forwarded_ns, source_ns), id";
    sqlite3_prepare_v2(db_.get(), select.c_str(), -1, &raw, nullptr);
    base::StmtPtr rows(raw);
    std::uint64_t count = 0;
    int step = SQLITE_ROW;
    while ((step = sqlite3_step(raw)) == SQLITE_ROW) {
        const std::string topic = text_column(raw, 0);
        const std::string fate = text_column(raw, 4);
        SampleRecord sample;
        sample.type_name = text_column(raw, 1);
        sample.source_ns = sqlite3_column_int64(raw, 3);
        sample.lifespan_ns = optional_column(raw, 9);
        if (sqlite3_column_type(raw, 10) != SQLITE_NULL)
            sample.instance = blob_column(raw, 10);
        if (fate == "received") {
            sample.topic = topic;
            sample.payload = blob_column(raw, 2);
            sample.receive_ns = sqlite3_column_int64(raw, 6);
        } else if (fate == "dropped" && sqlite3_column_int(raw, 11) != 0) {
            // Dropped on the robot, then backfilled: the camp has it on its own topic.
            sample.topic = topic;
            sample.payload = blob_column(raw, 2);
            sample.receive_ns = optional_column(raw, 6).value_or(sample.source_ns);
            sample.backfill = BackfillOrigin{std::string(), 0, text_column(raw, 5)};
        } else if (fate == "dropped") {
            sample.topic = "dropped/" + text_column(raw, 5) + "/" + topic;
            sample.payload = blob_column(raw, 2);
            sample.receive_ns = optional_column(raw, 7).value_or(sample.source_ns);
        } else {
            // Lost on the link: the robot kept its size, not its bytes.
            sample.topic = "lost/" + topic;
            sample.type_name.clear();
            sample.receive_ns = optional_column(raw, 8).value_or(sample.source_ns);
        }
        into.add(std::move(sample));
        ++count;
    }
    if (step != SQLITE_DONE)
        throw base::ConfigError(flag_ + ": reading '" + path_ + "' failed: " + sqlite3_errmsg(db_.get()));
    return count;
}

std::uint64_t RecordingReader::read_recording(SampleConsumer& into) {
    sqlite3* raw_db = db_.get();

    // Recordings made before the table existed have no announced types.
    const std::string topics_query =
        has_table(raw_db, "announced_types")
            ? "SELECT t.topic, t.type_name, t.lifespan_ns, t.keyed, t.reliable, t.discovered_ns, a.idl FROM topics t "
              "LEFT JOIN announced_types a ON a.type_name = t.type_name ORDER BY t.topic"
            : "SELECT topic, type_name, lifespan_ns, keyed, reliable, discovered_ns, NULL FROM topics ORDER BY topic";
    sqlite3_stmt* raw = nullptr;
    sqlite3_prepare_v2(raw_db, topics_query.c_str(), -1, &raw, nullptr);
    base::StmtPtr topics(raw);
    while (sqlite3_step(raw) == SQLITE_ROW) {
        TopicRecord topic;
        topic.topic = text_column(raw, 0);
        topic.type_name = text_column(raw, 1);
        topic.lifespan_ns = optional_column(raw, 2);
        topic.keyed = sqlite3_column_int(raw, 3) != 0;
        topic.reliable = sqlite3_column_int(raw, 4) != 0;
        topic.discovered_ns = sqlite3_column_int64(raw, 5);
        topic.announced_idl = text_column(raw, 6);
        into.add_topic(std::move(topic));
    }

    // A backfilled sample takes its place at its source time; recordings made before backfill have none.
    const std::string backfill_columns = has_column(raw_db, "samples", "backfilled")
                                             ? "backfilled, log_id, row_id, drop_reason"
                                             : "0 AS backfilled, NULL, NULL, NULL";
    const std::string select = "SELECT topic, type_name, payload, source_ns, receive_ns, lifespan_ns, instance, " +
                               backfill_columns +
                               " FROM samples ORDER BY CASE WHEN backfilled THEN source_ns ELSE receive_ns END, id";
    sqlite3_prepare_v2(raw_db, select.c_str(), -1, &raw, nullptr);
    base::StmtPtr samples(raw);
    std::uint64_t count = 0;
    int step = SQLITE_ROW;
    while ((step = sqlite3_step(raw)) == SQLITE_ROW) {
        SampleRecord sample;
        sample.topic = text_column(raw, 0);
        sample.type_name = text_column(raw, 1);
        sample.payload = blob_column(raw, 2);
        sample.source_ns = sqlite3_column_int64(raw, 3);
        sample.receive_ns = sqlite3_column_int64(raw, 4);
        sample.lifespan_ns = optional_column(raw, 5);
        if (sqlite3_column_type(raw, 6) != SQLITE_NULL)
            sample.instance = blob_column(raw, 6);
        if (sqlite3_column_int(raw, 7) != 0)
            sample.backfill = BackfillOrigin{text_column(raw, 8), sqlite3_column_int64(raw, 9), text_column(raw, 10)};
        into.add(std::move(sample));
        ++count;
    }
    if (step != SQLITE_DONE)
        throw base::ConfigError(flag_ + ": reading '" + path_ + "' failed: " + sqlite3_errmsg(raw_db));
    return count;
}

}  // namespace tgw::basecamp
