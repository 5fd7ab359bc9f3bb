#include "basecamp/analysis/drop_accounting.hpp"

#include <sqlite3.h>

#include <map>
#include <memory>
#include <set>

#include "base/config_error.hpp"
#include "base/sqlite_handles.hpp"
#include "basecamp/analysis/paper_message.hpp"
#include "basecamp/recording/read_only_db.hpp"

namespace tgw::basecamp {

namespace {

/// Source timestamps to the microsecond: the gateway republishes with the source timestamp it was given, but
/// each RTPS hop converts it to 2^-32 s fractions and back, so the two files may differ by a nanosecond.
std::int64_t micros(std::int64_t ns) {
    return ns >= 0 ? (ns + 500) / 1000 : -((-ns + 500) / 1000);
}

/// The identity of a sample within one topic.
class SampleKeys {
  public:
    explicit SampleKeys(bool by_sequence) : by_sequence_(by_sequence) {}

    /// Adds the key; false when it was there already.
    bool insert(const std::optional<std::uint32_t>& sequence, std::int64_t source_ns) {
        return keys_.insert(key(sequence, source_ns)).second;
    }

    bool contains(const std::optional<std::uint32_t>& sequence, std::int64_t source_ns) const {
        const std::int64_t k = key(sequence, source_ns);
        if (by_sequence_)
            return keys_.count(k) > 0;
        return keys_.count(k) > 0 || keys_.count(k - 1) > 0 || keys_.count(k + 1) > 0;
    }

  private:
    std::int64_t key(const std::optional<std::uint32_t>& sequence, std::int64_t source_ns) const {
        return by_sequence_ ? static_cast<std::int64_t>(*sequence) : micros(source_ns);
    }

    bool by_sequence_;
    std::set<std::int64_t> keys_;
};

std::optional<std::size_t> reason_index(const std::string& reason) {
    for (std::size_t i = 0; i < core::DROP_REASON_COUNT; ++i)
        if (core::DROP_REASON_NAMES[i] == reason)
            return i;
    return std::nullopt;
}

}  // namespace

std::uint64_t DropAccounting::dropped_total() const {
    std::uint64_t total = dropped_other;
    for (std::uint64_t n : dropped)
        total += n;
    return total;
}

DropAccounting account_topic(const std::vector<ReceivedSample>& received, const std::vector<LoggedSample>& logged,
                             std::optional<double> ttl_s, std::optional<std::uint64_t> offered,
                             std::optional<std::uint64_t> forwarded) {
    DropAccounting a;
    a.offered = offered;
    a.by_sequence = true;
    for (const ReceivedSample& s : received)
        a.by_sequence = a.by_sequence && s.sequence.has_value();
    for (const LoggedSample& s : logged)
        a.by_sequence = a.by_sequence && s.sequence.has_value();

    SampleKeys arrived(a.by_sequence);
    std::uint64_t on_time = 0;
    for (const ReceivedSample& s : received) {
        if (!arrived.insert(s.sequence, s.source_ns)) {
            ++a.duplicates_received;
            continue;
        }
        ++a.received;
        if (ttl_s && s.transit_ms <= *ttl_s * 1e3)
            ++on_time;
    }
    if (ttl_s)
        a.on_time = on_time;

    SampleKeys seen_in_log(a.by_sequence);
    for (const LoggedSample& s : logged) {
        if (!seen_in_log.insert(s.sequence, s.source_ns))
            continue;  // a sample is logged once; a repeated row adds nothing
        if (arrived.contains(s.sequence, s.source_ns)) {
            ++a.logged_and_received;
            continue;
        }
        if (const auto i = reason_index(s.reason))
            ++a.dropped[*i];
        else
            ++a.dropped_other;
    }

    // Rows with a reason this build does not know are not in a column: they count as unaccounted.
    const auto signed_count = [](std::uint64_t n) { return static_cast<std::int64_t>(n); };
    std::uint64_t known_drops = 0;
    for (std::uint64_t n : a.dropped)
        known_drops += n;
    if (forwarded) {
        const std::int64_t lost = signed_count(*forwarded) - signed_count(a.received);
        a.lost_on_link = static_cast<std::uint64_t>(lost > 0 ? lost : 0);
        a.lost_inferred = false;
        if (offered)
            a.unaccounted = signed_count(*offered) - signed_count(a.received) - signed_count(known_drops) -
                            signed_count(*a.lost_on_link);
    } else if (offered) {
        const std::int64_t rest = signed_count(*offered) - signed_count(a.received) - signed_count(a.dropped_total());
        a.lost_on_link = static_cast<std::uint64_t>(rest > 0 ? rest : 0);
        a.unaccounted = rest - signed_count(*a.lost_on_link) + signed_count(a.dropped_other);
    }
    return a;
}

std::vector<LoggedSample> read_robot_log(const std::string& path, const std::string& flag, std::int64_t since_ns) {
    const base::DbPtr db = open_read_only(path, flag);
    sqlite3_stmt* stmt_raw = nullptr;
    if (sqlite3_prepare_v2(db.get(),
                           "SELECT topic, type_name, payload, source_time_ns, reason FROM dropped_samples "
                           "WHERE source_time_ns >= ?1 ORDER BY id",
                           -1, &stmt_raw, nullptr) != SQLITE_OK)
        throw base::ConfigError(flag + ": '" + path +
                                "' is not an on-robot log (table dropped_samples): " + sqlite3_errmsg(db.get()));
    base::StmtPtr stmt(stmt_raw);
    sqlite3_bind_int64(stmt.get(), 1, since_ns);
    std::vector<LoggedSample> rows;
    int rc = SQLITE_ROW;
    while ((rc = sqlite3_step(stmt.get())) == SQLITE_ROW) {
        LoggedSample row;
        const auto* topic = reinterpret_cast<const char*>(sqlite3_column_text(stmt.get(), 0));
        const auto* type_name = reinterpret_cast<const char*>(sqlite3_column_text(stmt.get(), 1));
        const auto* reason = reinterpret_cast<const char*>(sqlite3_column_text(stmt.get(), 4));
        row.topic = topic ? topic : "";
        row.reason = reason ? reason : "";
        row.source_ns = sqlite3_column_int64(stmt.get(), 3);
        if (type_name != nullptr && std::string(type_name) == PAPER_MESSAGE_TYPE)
            row.sequence = paper_message_sequence(static_cast<const std::uint8_t*>(sqlite3_column_blob(stmt.get(), 2)),
                                                  static_cast<std::size_t>(sqlite3_column_bytes(stmt.get(), 2)));
        rows.push_back(std::move(row));
    }
    if (rc != SQLITE_DONE)
        throw base::ConfigError(flag + ": cannot read '" + path + "': " + sqlite3_errmsg(db.get()));
    return rows;
}

}  // namespace tgw::basecamp
