#include "gateway/dds/lane_listener.hpp"

#include <algorithm>
#include <iostream>
#include <utility>

#include <fastdds/dds/subscriber/DataReader.hpp>
#include <fastdds/dds/subscriber/SampleInfo.hpp>

#include "passthrough/dds_time.hpp"
#include "passthrough/passthrough_type.hpp"
#include "passthrough/take_each.hpp"

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
                           const passthrough::LaneAssignment& lanes, core::ForwardingLoop& loop,
                           const base::Clock& clock, std::shared_ptr<const types::KeyHasher> key_hasher)
    : topic_(topic),
      name_(std::move(name)),
      lane_(lane),
      keyed_(keyed),
      lanes_(lanes),
      loop_(loop),
      clock_(clock),
      key_hasher_(std::move(key_hasher)) {}

void LaneListener::on_data_available(fdds::DataReader* reader) {
    // Fast DDS may call this from the SHM and the UDP receive threads at once: samples go to the loop in the
    // order they were taken.
    std::lock_guard<std::mutex> lock(take_order_);
    passthrough::take_each<passthrough::PassthroughData>(
        *reader, [this](passthrough::PassthroughData& data, const fdds::SampleInfo& info) {
            if (!lanes_.carries(info.publication_handle, lane_)) {
                return;  // the writer's own lane carries it
            }
            core::Sample sample;
            sample.kind = kind_of(info);
            if (sample.kind != core::SampleKind::data && !keyed_) {
                return;  // an unkeyed topic's one instance: nothing for the base camp to learn
            }
            sample.topic = topic_;
            sample.route = lane_;
            if (sample.kind == core::SampleKind::data) {
                sample.payload = std::move(data.payload);
            }
            data.payload = {};
            if (keyed_) {
                set_key(info, sample);
            }
            if (const auto source = passthrough::to_wall_time(info.source_timestamp)) {
                sample.source_time = *source;
            } else {
                sample.source_time = clock_.wall_now();
                stamped_on_arrival_.fetch_add(1, std::memory_order_relaxed);
            }
            loop_.submit(std::move(sample));
        });
}

void LaneListener::set_key(const fdds::SampleInfo& info, core::Sample& sample) {
    const bool sent =
        info.instance_handle.isDefined() && info.instance_handle != passthrough::PassthroughType::UNKNOWN_INSTANCE;
    if (sent) {
        const eprosima::fastrtps::rtps::octet* hash = info.instance_handle.value;
        std::copy(hash, hash + sample.key.bytes.size(), sample.key.bytes.begin());
        sample.key.valid = true;
    }
    // A dispose or unregister without a key hash carries no payload to compute it from.
    if (key_hasher_ == nullptr || sample.payload.empty()) {
        if (!sent && without_key_hash_.fetch_add(1, std::memory_order_relaxed) == 0) {
            std::cerr << "telemetry-gateway: " << name_
                      << ": keyed, but its publisher sends no key hash and the gateway has no IDL of its type; "
                         "base-camp readers still tell the instances apart, the gateway's history (a latched "
                         "topic's last sample per instance) cannot. Give the type's IDL with --idl DIR, or make the "
                         "publisher send it (Cyclone DDS: <Internal><GenerateKeyhash>true</GenerateKeyhash>"
                         "</Internal>)\n";
        }
        return;
    }
    // With a key hash sent, the first sample checks the IDL against the publisher's type.
    if (sent && publisher_hash_checked_) {
        return;
    }
    std::string why;
    const std::optional<types::KeyHash> computed = key_hasher_->hash(sample.payload.data(), sample.payload.size(), why);
    if (sent) {
        publisher_hash_checked_ = true;
        if (computed && *computed != sample.key.bytes) {
            std::cerr << "telemetry-gateway: " << name_
                      << ": the key hash computed from the type's IDL (--idl) differs from the one its publisher "
                         "sent: the IDL is not the publisher's type, or not as it serializes its key. The "
                         "publisher's is used\n";
        }
        return;
    }
    if (computed) {
        sample.key.bytes = *computed;
        sample.key.valid = true;
        key_hash_computed_.fetch_add(1, std::memory_order_relaxed);
    } else if (without_key_hash_.fetch_add(1, std::memory_order_relaxed) == 0) {
        std::cerr << "telemetry-gateway: " << name_
                  << ": keyed, its publisher sends no key hash, and a sample does not decode as the type's IDL "
                     "(--idl), so the gateway cannot compute it: "
                  << why << "\n";
    }
}

void LaneListener::on_subscription_matched(fdds::DataReader* /*reader*/, const fdds::SubscriptionMatchedStatus& info) {
    matched_.store(info.current_count);
}

}  // namespace tgw::dds
