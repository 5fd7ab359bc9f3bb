#include "gateway/dds/grant_reader.hpp"

#include <algorithm>

#include <fastdds/dds/subscriber/DataReader.hpp>
#include <fastdds/dds/subscriber/SampleInfo.hpp>

#include "ChannelGrantPubSubTypes.h"
#include "passthrough/take_each.hpp"
#include "wire/channel_grant_topic.hpp"

namespace tgw::dds {

GrantReader::GrantReader(const eprosima::fastrtps::rtps::GuidPrefix_t& own, const base::Clock& clock,
                         std::function<void()> changed)
    : clock_(clock), changed_(std::move(changed)), own_(own), join_until_(clock.now() + core::JOIN_WAIT) {}

void GrantReader::set_own(const eprosima::fastrtps::rtps::GuidPrefix_t& own) {
    std::lock_guard<std::mutex> lock(mutex_);
    own_ = own;
    own_grant_ = Heard{};
}

void GrantReader::on_data_available(eprosima::fastdds::dds::DataReader* reader) {
    bool ours = false;
    passthrough::take_valid<idl::ChannelGrant>(
        *reader, [&](const idl::ChannelGrant& grant, const eprosima::fastdds::dds::SampleInfo& /*info*/) {
            const auto& prefix = grant.gateway_prefix();
            std::lock_guard<std::mutex> lock(mutex_);
            Heard* heard = nullptr;
            if (std::equal(prefix.begin(), prefix.end(), std::begin(own_.value))) {
                heard = &own_grant_;
            } else if (prefix == wire::NEWCOMER_PREFIX) {
                heard = &newcomer_;
            } else {
                return;  // another gateway's
            }
            heard->rate_bps = std::max(0.0, grant.rate_bps());
            heard->valid_until = clock_.now() + std::chrono::milliseconds(grant.valid_ms());
            ours = true;
        });
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
    return view().grant_bps;
}

core::GrantView GrantReader::view() const {
    const base::SteadyTime now = clock_.now();
    std::lock_guard<std::mutex> lock(mutex_);
    core::GrantView out;
    out.grant_bps = own_grant_.in_force(now);
    out.newcomer_bps = newcomer_.in_force(now);
    out.joining = !own_grant_.rate_bps && !newcomer_.rate_bps && now < join_until_;
    return out;
}

std::optional<double> GrantReader::Heard::in_force(base::SteadyTime now) const {
    return now < valid_until ? rate_bps : std::nullopt;
}

}  // namespace tgw::dds
