#include "gateway/dds/grant_reader.hpp"

#include <algorithm>

#include <fastdds/dds/subscriber/DataReader.hpp>
#include <fastdds/dds/subscriber/SampleInfo.hpp>

#include "ChannelGrantPubSubTypes.h"

namespace tgw::dds {

GrantReader::GrantReader(const eprosima::fastrtps::rtps::GuidPrefix_t& own, const base::Clock& clock,
                         std::function<void()> changed)
    : own_(own), clock_(clock), changed_(std::move(changed)) {}

void GrantReader::on_data_available(eprosima::fastdds::dds::DataReader* reader) {
    idl::ChannelGrant grant;
    eprosima::fastdds::dds::SampleInfo info;
    bool ours = false;
    while (reader->take_next_sample(&grant, &info) == ReturnCode_t::RETCODE_OK) {
        if (!info.valid_data ||
            !std::equal(grant.gateway_prefix().begin(), grant.gateway_prefix().end(), std::begin(own_.value))) {
            continue;  // another gateway's
        }
        std::lock_guard<std::mutex> lock(mutex_);
        rate_bps_ = std::max(0.0, grant.rate_bps());
        valid_until_ = clock_.now() + std::chrono::milliseconds(grant.valid_ms());
        ours = true;
    }
    std::lock_guard<std::mutex> lock(changed_mutex_);
    if (ours && changed_ && !closed_) {
        changed_();
    }
}

void GrantReader::close() {
    std::lock_guard<std::mutex> lock(changed_mutex_);
    closed_ = true;
}

std::optional<double> GrantReader::current() const {
    std::lock_guard<std::mutex> lock(mutex_);
    if (!rate_bps_ || clock_.now() >= valid_until_) {
        return std::nullopt;
    }
    return rate_bps_;
}

}  // namespace tgw::dds
