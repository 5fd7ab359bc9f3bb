#include "basecamp/capture/backfill_archive.hpp"

#include "wire/backfill_codec.hpp"

namespace tgw::basecamp {

BackfillArchive::BackfillArchive(SampleStore& store) : store_(store) {
    store_.on_backfill_stored([this](const std::string& log_id, std::int64_t row_id) { stored(log_id, row_id); });
}

BackfillArchive::~BackfillArchive() {
    store_.on_backfill_stored({});
}

void BackfillArchive::take(const idl::BackfillSample& sample, std::int64_t receive_ns) {
    received_.fetch_add(1, std::memory_order_relaxed);
    SampleRecord record;
    record.topic = sample.topic();
    record.type_name = sample.type_name();
    record.payload = sample.payload();
    record.source_ns = sample.source_ns();
    record.receive_ns = receive_ns;
    if (sample.deadline_ns() > sample.source_ns()) {
        record.lifespan_ns = sample.deadline_ns() - sample.source_ns();  // its TTL on the robot
    }
    if (sample.keyed()) {
        record.instance.assign(sample.instance().begin(), sample.instance().end());
    }
    record.backfill =
        BackfillOrigin{wire::log_id_hex(sample.log_id()), static_cast<std::int64_t>(sample.row_id()), sample.reason()};
    store_.add(std::move(record));
}

void BackfillArchive::stored(const std::string& log_id, std::int64_t row_id) {
    const std::optional<std::array<std::uint8_t, 16>> octets = wire::log_id_octets(log_id);
    if (!octets) {
        return;  // never one the camp was sent: take() writes only well-formed ids
    }
    std::lock_guard<std::mutex> lock(mutex_);
    committed_[*octets].push_back(row_id);
}

std::vector<idl::BackfillAck> BackfillArchive::take_acks(std::uint64_t sent_ns) {
    std::map<std::array<std::uint8_t, 16>, std::vector<std::int64_t>> committed;
    {
        std::lock_guard<std::mutex> lock(mutex_);
        committed.swap(committed_);
    }
    std::vector<idl::BackfillAck> acks;
    for (auto& [log_id, rows] : committed) {
        acknowledged_.fetch_add(rows.size(), std::memory_order_relaxed);
        idl::BackfillAck ack;
        ack.log_id(log_id);
        for (const auto& [first, last] : wire::row_ranges(std::move(rows))) {
            idl::BackfillRowRange range;
            range.first_row_id(static_cast<std::uint64_t>(first));
            range.last_row_id(static_cast<std::uint64_t>(last));
            ack.rows().push_back(range);
        }
        ack.sent_ns(sent_ns);
        acks.push_back(std::move(ack));
    }
    return acks;
}

}  // namespace tgw::basecamp
