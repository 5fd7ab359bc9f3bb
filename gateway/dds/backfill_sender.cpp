#include "gateway/dds/backfill_sender.hpp"

#include <algorithm>
#include <iostream>

#include "wire/backfill_codec.hpp"

namespace tgw::dds {

idl::BackfillSample backfill_sample(const log::StoredSample& row, const std::array<std::uint8_t, 16>& log_id) {
    idl::BackfillSample sample;
    sample.row_id(static_cast<std::uint64_t>(row.row_id));
    sample.log_id(log_id);
    sample.topic(row.topic);
    sample.type_name(row.type_name);
    sample.source_ns(base::to_ns(row.source_time));
    sample.deadline_ns(base::to_ns(row.deadline));
    sample.reason(row.reason);
    sample.kind(static_cast<std::uint8_t>(row.kind));
    sample.keyed(row.key.valid);
    if (row.key.valid)
        sample.instance(row.key.bytes);
    sample.payload(row.payload);
    return sample;
}

namespace {

std::array<std::uint8_t, 16> octets_of(const std::string& log_id) {
    const std::optional<std::array<std::uint8_t, 16>> octets = wire::log_id_octets(log_id);
    if (!octets) {
        std::cerr << "telemetry-gateway: the on-robot log's id '" << log_id << "' is not 32 hex characters\n";
        return {};
    }
    return *octets;
}

}  // namespace

BackfillSender::BackfillSender(log::RobotLog& log, Config config, core::WireModel wire, const base::Clock& clock,
                               std::function<void()> wake_loop)
    : log_(log),
      config_(config),
      wire_(wire),
      clock_(clock),
      wake_loop_(std::move(wake_loop)),
      log_id_(octets_of(log.log_id())),
      planner_(config.planner) {}

BackfillSender::~BackfillSender() {
    stop();
}

void BackfillSender::start(core::TopicId topic) {
    topic_ = topic;
    thread_ = std::thread([this] { run(); });
}

void BackfillSender::stop() {
    {
        std::lock_guard<std::mutex> lock(mutex_);
        stopping_ = true;
    }
    wake_.notify_all();
    if (thread_.joinable())
        thread_.join();
}

void BackfillSender::run() {
    std::unique_lock<std::mutex> lock(mutex_);
    while (!stopping_) {
        lock.unlock();
        read_new_rows();
        const bool ready = read_ahead(clock_.now());
        lock.lock();
        if (ready && told_none_) {
            told_none_ = false;
            lock.unlock();
            wake_loop_();
            lock.lock();
        }
        // Woken early when the loop takes a sample: room to read ahead.
        wake_.wait_for(lock, config_.poll, [this] { return stopping_ || refill_; });
        refill_ = false;
    }
}

void BackfillSender::read_new_rows() {
    for (;;) {
        const std::vector<log::BackfillCandidate> page = log_.unacknowledged(read_up_to_, config_.page_rows);
        if (page.empty())
            return;
        {
            std::lock_guard<std::mutex> lock(mutex_);
            for (const log::BackfillCandidate& row : page) {
                planner_.add(core::BackfillRow{
                    row.row_id, std::chrono::duration_cast<base::Duration>(row.deadline - row.source_time),
                    row.source_time, row.payload_bytes});
            }
        }
        read_up_to_ = page.back().row_id;
        if (page.size() < config_.page_rows)
            return;
    }
}

bool BackfillSender::read_ahead(base::SteadyTime now) {
    bool any = false;
    for (;;) {
        std::optional<core::BackfillRow> row;
        {
            std::lock_guard<std::mutex> lock(mutex_);
            if (stopping_ || ready_.size() >= config_.read_ahead)
                return any;
            row = planner_.take(now);
        }
        if (!row)
            return any;
        const std::optional<log::StoredSample> stored = log_.read_dropped(row->id);
        std::vector<std::uint8_t> payload;
        if (stored)
            payload = wire::encode_backfill(backfill_sample(*stored, log_id_));
        std::lock_guard<std::mutex> lock(mutex_);
        if (payload.empty()) {
            planner_.forget(row->id);  // pruned at the cap before the camp had it, or unreadable
            continue;
        }
        core::Sample sample;
        sample.topic = topic_;
        sample.payload = std::move(payload);
        sample.source_time = stored->source_time;
        ready_.push_back(std::move(sample));
        any = true;
    }
}

std::optional<core::Sample> BackfillSender::next_when_idle(base::SteadyTime /*now*/) {
    std::lock_guard<std::mutex> lock(mutex_);
    if (ready_.empty()) {
        told_none_ = true;
        return std::nullopt;
    }
    core::Sample sample = std::move(ready_.front());
    ready_.pop_front();
    refill_ = true;
    wake_.notify_all();
    return sample;
}

std::optional<base::SteadyTime> BackfillSender::next_ready(base::SteadyTime now) const {
    std::lock_guard<std::mutex> lock(mutex_);
    return ready_.empty() ? std::nullopt : std::optional<base::SteadyTime>(now);
}

void BackfillSender::left(std::int64_t row_id, std::size_t payload_bytes) {
    {
        std::lock_guard<std::mutex> lock(mutex_);
        planner_.sent(row_id, wire_.wire_bits(payload_bytes), clock_.now());
        ++counts_.sent;
    }
    log_.mark_sent(row_id, clock_.wall_now());
}

void BackfillSender::not_left(std::int64_t row_id) {
    std::lock_guard<std::mutex> lock(mutex_);
    planner_.not_sent(row_id);
    ++counts_.not_sent;
}

void BackfillSender::acknowledged(const std::array<std::uint8_t, 16>& log_id,
                                  const std::vector<std::pair<std::int64_t, std::int64_t>>& ranges) {
    if (log_id != log_id_)
        return;
    const base::WallTime now = clock_.wall_now();
    {
        std::lock_guard<std::mutex> lock(mutex_);
        for (const auto& [first, last] : ranges)
            counts_.acknowledged += planner_.acknowledged(first, last);
        // A row read ahead that the camp has already: not sent again.
        ready_.erase(std::remove_if(ready_.begin(), ready_.end(),
                                    [&](const core::Sample& sample) {
                                        const std::optional<std::int64_t> row = wire::backfill_row_id(sample.payload);
                                        return row && std::any_of(ranges.begin(), ranges.end(), [&](const auto& r) {
                                                   return *row >= r.first && *row <= r.second;
                                               });
                                    }),
                     ready_.end());
    }
    for (const auto& [first, last] : ranges)
        log_.mark_acknowledged(first, last, now);
}

core::BackfillPlanner::Backlog BackfillSender::backlog() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return planner_.backlog();
}

BackfillSender::Counts BackfillSender::counts() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return counts_;
}

}  // namespace tgw::dds
