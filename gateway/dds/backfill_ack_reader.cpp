#include "gateway/dds/backfill_ack_reader.hpp"

#include <fastdds/dds/subscriber/DataReader.hpp>
#include <fastdds/dds/subscriber/SampleInfo.hpp>

#include "BackfillPubSubTypes.h"
#include "gateway/dds/backfill_sender.hpp"
#include "passthrough/take_each.hpp"

namespace tgw::dds {

void BackfillAckReader::on_data_available(eprosima::fastdds::dds::DataReader* reader) {
    passthrough::take_valid<idl::BackfillAck>(
        *reader, [this](const idl::BackfillAck& ack, const eprosima::fastdds::dds::SampleInfo& /*info*/) {
            std::vector<std::pair<std::int64_t, std::int64_t>> ranges;
            ranges.reserve(ack.rows().size());
            for (const idl::BackfillRowRange& range : ack.rows()) {
                if (range.first_row_id() <= range.last_row_id())
                    ranges.emplace_back(static_cast<std::int64_t>(range.first_row_id()),
                                        static_cast<std::int64_t>(range.last_row_id()));
            }
            std::lock_guard<std::mutex> lock(mutex_);
            if (sender_ != nullptr)
                sender_->acknowledged(ack.log_id(), ranges);
        });
}

void BackfillAckReader::close() {
    std::lock_guard<std::mutex> lock(mutex_);
    sender_ = nullptr;
}

}  // namespace tgw::dds
