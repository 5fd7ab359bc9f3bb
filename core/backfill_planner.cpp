#include "core/backfill_planner.hpp"

#include <algorithm>

namespace tgw::core {

BackfillPlanner::BackfillPlanner(BackfillConfig config) : config_(config) {}

void BackfillPlanner::add(const BackfillRow& row) {
    if (!rows_.emplace(row.id, Entry{row}).second)
        return;
    ready_.insert(order_key(row));
    by_age_.emplace(row.source_time, row.id);
    bytes_ += row.bytes;
}

void BackfillPlanner::resend_due(base::SteadyTime now) {
    while (!waiting_.empty() && waiting_.begin()->first <= now) {
        Entry& entry = rows_.at(waiting_.begin()->second);
        waiting_.erase(waiting_.begin());
        entry.state = State::ready;
        ready_.insert(order_key(entry.row));
    }
}

std::optional<BackfillRow> BackfillPlanner::take(base::SteadyTime now) {
    resend_due(now);
    if (ready_.empty() || now < cap_free_at_)
        return std::nullopt;
    const std::int64_t id = std::get<2>(*ready_.begin());
    ready_.erase(ready_.begin());
    Entry& entry = rows_.at(id);
    entry.state = State::taken;
    return entry.row;
}

void BackfillPlanner::sent(std::int64_t id, std::uint64_t wire_bits, base::SteadyTime now) {
    if (config_.max_bps > 0.0) {
        cap_free_at_ =
            std::max(cap_free_at_, now) + base::from_seconds(static_cast<double>(wire_bits) / config_.max_bps);
    }
    const auto it = rows_.find(id);
    if (it == rows_.end() || it->second.state != State::taken)
        return;
    it->second.state = State::sent;
    it->second.resend_at = now + config_.resend_after;
    waiting_.emplace(it->second.resend_at, id);
}

void BackfillPlanner::not_sent(std::int64_t id) {
    const auto it = rows_.find(id);
    if (it == rows_.end() || it->second.state != State::taken)
        return;
    it->second.state = State::ready;
    ready_.insert(order_key(it->second.row));
}

void BackfillPlanner::acknowledged(std::int64_t id) {
    const auto it = rows_.find(id);
    if (it != rows_.end())
        erase(it);
}

std::size_t BackfillPlanner::acknowledged(std::int64_t first, std::int64_t last) {
    std::size_t known = 0;
    for (auto it = rows_.lower_bound(first); it != rows_.end() && it->first <= last; ++known)
        erase(it++);
    return known;
}

void BackfillPlanner::forget(std::int64_t id) {
    acknowledged(id);
}

void BackfillPlanner::erase(std::map<std::int64_t, Entry>::iterator it) {
    const Entry& entry = it->second;
    switch (entry.state) {
        case State::ready:
            ready_.erase(order_key(entry.row));
            break;
        case State::sent:
            waiting_.erase({entry.resend_at, entry.row.id});
            break;
        case State::taken:
            break;  // its sender's sent() or not_sent() will find it gone
    }
    by_age_.erase({entry.row.source_time, entry.row.id});
    bytes_ -= entry.row.bytes;
    rows_.erase(it);
}

std::optional<base::SteadyTime> BackfillPlanner::next_wakeup(base::SteadyTime now) const {
    std::optional<base::SteadyTime> wakeup;
    if (!ready_.empty())
        wakeup = std::max(now, cap_free_at_);
    if (!waiting_.empty()) {
        const base::SteadyTime resend = std::max({now, cap_free_at_, waiting_.begin()->first});
        wakeup = wakeup ? std::min(*wakeup, resend) : resend;
    }
    return wakeup;
}

BackfillPlanner::Backlog BackfillPlanner::backlog() const {
    Backlog backlog{rows_.size(), bytes_, std::nullopt};
    if (!by_age_.empty())
        backlog.oldest = by_age_.begin()->first;
    return backlog;
}

}  // namespace tgw::core
