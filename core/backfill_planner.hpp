// Backfill (docs/design/backfill.md): the samples the on-robot log holds, which never reached the base camp, cross
// the link in capacity no live sample wants, until the camp says it has stored each. The planner decides which row
// goes next and when one goes again; the schedule decides when the link is free for it (Scheduler::IdleSource).
#pragma once

#include <cstddef>
#include <cstdint>
#include <map>
#include <optional>
#include <set>
#include <tuple>
#include <utility>

#include "base/time.hpp"

namespace tgw::core {

/// A row of the on-robot log that the base camp has not acknowledged, as the planner orders it.
struct BackfillRow {
    std::int64_t id = 0;         ///< the log's row id: names the row for ever, with the log's id
    base::Duration ttl{};        ///< the sample's TTL: the shorter, the more valuable its late copy
    base::WallTime source_time;  ///< when it was born: the older first among equals
    std::size_t bytes = 0;       ///< its payload, for the backlog's size
};

struct BackfillConfig {
    /// A row sent without an acknowledgement for this long goes again: it, or its acknowledgement, was lost.
    base::Duration resend_after = std::chrono::seconds(5);
    /// The most bit/s backfill may take (a link billed per byte); 0: only the schedule's budget bounds it.
    double max_bps = 0.0;
};

/// The order in which rows go, and their state: ready, taken by the sender, sent and waiting for the camp's
/// acknowledgement. Most valuable first: shortest TTL first (a hazard's late copy before a picture's), oldest first
/// within one TTL, the log's order last. Pure: no clock of its own, no threads, no I/O.
class BackfillPlanner {
  public:
    explicit BackfillPlanner(BackfillConfig config);

    /// A row the camp has not acknowledged. A row known already is left as it is.
    void add(const BackfillRow& row);
    /// The most valuable ready row, now taken by the sender until sent() or not_sent() tells its fate; nullopt when
    /// none is ready or the cap holds the next back. Rows sent without acknowledgement for resend_after are ready
    /// again first.
    std::optional<BackfillRow> take(base::SteadyTime now);
    /// The row taken left at `now`, `wire_bits` on the link: it waits for its acknowledgement, and the cap counts the
    /// bits (a row unknown by now counts for the cap only).
    void sent(std::int64_t id, std::uint64_t wire_bits, base::SteadyTime now);
    /// The row taken never reached the link (the schedule dropped it, its write failed): ready again at once.
    void not_sent(std::int64_t id);
    /// The camp has stored the row: it never goes again, and leaves the backlog. It may come for a row in any state
    /// (a gateway that restarted sends again what the camp had) or for one not known here, which changes nothing.
    void acknowledged(std::int64_t id);
    /// acknowledged() for every known row from `first` to `last`, both included; returns how many were known.
    std::size_t acknowledged(std::int64_t first, std::int64_t last);
    /// The row is gone from the log (pruned at the cap before the camp had it): forget it.
    void forget(std::int64_t id);

    /// When take() may next hand out a row (now, if one is ready now); nullopt while every row is taken, or none is
    /// known.
    std::optional<base::SteadyTime> next_wakeup(base::SteadyTime now) const;

    /// Every row not acknowledged, those sent and taken included: the robot's copy is still the only sure one.
    struct Backlog {
        std::size_t rows = 0;
        std::uint64_t bytes = 0;
        std::optional<base::WallTime> oldest;  ///< the oldest source time
    };
    Backlog backlog() const;

  private:
    enum class State : std::uint8_t { ready, taken, sent };
    struct Entry {
        BackfillRow row;
        State state = State::ready;
        base::SteadyTime resend_at{};  ///< State::sent
    };
    /// The order of value: TTL, source time, id.
    using OrderKey = std::tuple<base::Duration, base::WallTime, std::int64_t>;
    static OrderKey order_key(const BackfillRow& row) { return {row.ttl, row.source_time, row.id}; }

    /// Rows whose resend time has come are ready again.
    void resend_due(base::SteadyTime now);
    /// Forgets `it` wherever it stands.
    void erase(std::map<std::int64_t, Entry>::iterator it);

    const BackfillConfig config_;
    std::map<std::int64_t, Entry> rows_;  ///< by id, for ranges of acknowledgements
    std::set<OrderKey> ready_;
    std::set<std::pair<base::SteadyTime, std::int64_t>> waiting_;  ///< sent rows, by resend time
    std::set<std::pair<base::WallTime, std::int64_t>> by_age_;     ///< every row, for the backlog's oldest
    std::uint64_t bytes_ = 0;
    base::SteadyTime cap_free_at_{};  ///< with a cap: when the next row may go
};

}  // namespace tgw::core
