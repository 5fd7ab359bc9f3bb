#include "gateway/dds/lane_listener.hpp"

#include <algorithm>
#include <iostream>
#include <utility>

#include <fastdds/dds/subscriber/DataReader.hpp>
#include <fastdds/dds/subscriber/SampleInfo.hpp>

#include "gateway/dds/dds_time.hpp"
#include "gateway/dds/passthrough_type.hpp"

namespace tgw::dds {

namespace fdds = eprosima::fastdds::dds;

namespace {

core::SampleKind kind_of(const fdds::SampleInfo& info) {
    if (info.valid_data) {
        return core::SampleKind::data;
    }
    return info.instance_state == fdds::NOT_ALIVE_DISPOSED_INSTANCE_STATE ? core::SampleKind::dispose
                                                                          : core::SampleKind::unregister;
}

}  // namespace

LaneListener::LaneListener(core::TopicId topic, std::string name, std::uint16_t lane, bool keyed,
                           const LaneAssignment& lanes, core::ForwardingLoop& loop, const base::Clock& clock)
    : topic_(topic), name_(std::move(name)), lane_(lane), keyed_(keyed), lanes_(lanes), loop_(loop), clock_(clock) {}

void LaneListener::on_data_available(fdds::DataReader* reader) {
    // Fast DDS may call this from the SHM and the UDP receive threads at once: samples go to the loop in the
    // order they were taken.
    std::lock_guard<std::mutex> lock(take_order_);
    PassthroughData data;
    fdds::SampleInfo info;
    while (reader->take_next_sample(&data, &info) == ReturnCode_t::RETCODE_OK) {
        if (!lanes_.carries(info.publication_handle, lane_)) {
            continue;  // the writer's own lane carries it
        }
        core::Sample sample;
        sample.kind = kind_of(info);
        if (sample.kind != core::SampleKind::data && !keyed_) {
            continue;  // an unkeyed topic's one instance: nothing for the base camp to learn
        }
        sample.topic = topic_;
        sample.route = lane_;
        if (sample.kind == core::SampleKind::data) {
            sample.payload = std::move(data.payload);
        }
        data.payload = {};
        if (keyed_ && info.instance_handle.isDefined() && info.instance_handle != PassthroughType::UNKNOWN_INSTANCE) {
            const eprosima::fastrtps::rtps::octet* hash = info.instance_handle.value;
            std::copy(hash, hash + sample.key.bytes.size(), sample.key.bytes.begin());
            sample.key.valid = true;
        } else if (keyed_ && without_key_hash_.fetch_add(1, std::memory_order_relaxed) == 0) {
            std::cerr << "telemetry-gateway: " << name_
                      << ": keyed, but its publisher sends no key hash; base-camp readers still tell the instances "
                         "apart, the gateway's history (a latched topic's last sample per instance) cannot. "
                         "Cyclone DDS sends it with <Internal><GenerateKeyhash>true</GenerateKeyhash></Internal>\n";
        }
        if (const auto source = to_wall_time(info.source_timestamp)) {
            sample.source_time = *source;
        } else {
            sample.source_time = clock_.wall_now();
            stamped_on_arrival_.fetch_add(1, std::memory_order_relaxed);
        }
        loop_.submit(std::move(sample));
    }
}

void LaneListener::on_subscription_matched(fdds::DataReader* /*reader*/, const fdds::SubscriptionMatchedStatus& info) {
    matched_.store(info.current_count);
}

}  // namespace tgw::dds
