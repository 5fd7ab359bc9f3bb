#include "gateway/dds/backfill_ack_reader.hpp"

#include <fastdds/dds/subscriber/DataReader.hpp>
#include <fastdds/dds/subscriber/SampleInfo.hpp>

#include "BackfillPubSubTypes.h"
#include "gateway/dds/backfill_sender.hpp"

namespace tgw::dds {

void BackfillAckReader::on_data_available(eprosima::fastdds::dds::DataReader* reader) {
    idl::BackfillAck ack;
    eprosima::fastdds::dds::SampleInfo info;
    while (reader->take_next_sample(&ack, &info) == ReturnCode_t::RETCODE_OK) {
        if (!info.valid_data)
            continue;
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
    }
}

void BackfillAckReader::close() {
    std::lock_guard<std::mutex> lock(mutex_);
    sender_ = nullptr;
}

}  // namespace tgw::dds
