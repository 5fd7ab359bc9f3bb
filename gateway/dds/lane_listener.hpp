#pragma once

#include <atomic>
#include <cstdint>
#include <memory>
#include <mutex>
#include <string>

#include <fastdds/dds/subscriber/DataReaderListener.hpp>
#include <fastdds/dds/subscriber/SampleInfo.hpp>

#include "base/clock.hpp"
#include "core/forwarding_loop.hpp"
#include "passthrough/lane_assignment.hpp"
#include "types/key_hash.hpp"

namespace tgw::dds {

/// The listener of one lane's type-agnostic reader on the robot domain: every sample it takes from a writer of
/// its lane (LaneAssignment) becomes a core::Sample (payload as received, instance from SampleInfo, the
/// publisher's source timestamp) and goes to the ForwardingLoop in the same thread. Disposes and unregisters
/// go the same way, without payload. The payload is copied once, from Fast DDS's cache into the sample's own
/// buffer, and moved from there on.
class LaneListener final : public eprosima::fastdds::dds::DataReaderListener {
  public:
    /// `lanes` must outlive the listener. `name`: the topic's, for the warnings about key hashes. `key_hasher`: the
    /// keyed topic's type from IDL (--idl), to compute the key hash a publisher did not send; null: none known.
    LaneListener(core::TopicId topic, std::string name, std::uint16_t lane, bool keyed,
                 const passthrough::LaneAssignment& lanes, core::ForwardingLoop& loop, const base::Clock& clock,
                 std::shared_ptr<const types::KeyHasher> key_hasher = nullptr);

    void on_data_available(eprosima::fastdds::dds::DataReader* reader) override;
    void on_subscription_matched(eprosima::fastdds::dds::DataReader* reader,
                                 const eprosima::fastdds::dds::SubscriptionMatchedStatus& info) override;

    core::TopicId topic() const { return topic_; }
    /// Robot-domain writers currently matched.
    std::int32_t matched_writers() const { return matched_.load(); }
    /// Samples that carried no source timestamp and were stamped on arrival.
    std::uint64_t stamped_on_arrival() const { return stamped_on_arrival_.load(); }
    /// Samples of a keyed topic whose instance the publisher did not send (no key hash) and the gateway could not
    /// compute (no IDL of the type, or a payload that does not decode as it): written all as one instance, so the
    /// gateway's per-instance history cannot keep them apart (base-camp readers still can: they compute the key
    /// from the payload).
    std::uint64_t without_key_hash() const { return without_key_hash_.load(); }
    /// Samples whose key hash the gateway computed from the payload and the type's IDL.
    std::uint64_t key_hash_computed() const { return key_hash_computed_.load(); }

  private:
    /// The sample's instance: the publisher's key hash, else the one computed from its payload.
    void set_key(const eprosima::fastdds::dds::SampleInfo& info, core::Sample& sample);

    const core::TopicId topic_;
    const std::string name_;
    const std::uint16_t lane_;
    const bool keyed_;
    const passthrough::LaneAssignment& lanes_;
    core::ForwardingLoop& loop_;
    const base::Clock& clock_;
    std::atomic<std::int32_t> matched_{0};
    std::atomic<std::uint64_t> stamped_on_arrival_{0};
    std::atomic<std::uint64_t> without_key_hash_{0};
    std::atomic<std::uint64_t> key_hash_computed_{0};
    const std::shared_ptr<const types::KeyHasher> key_hasher_;
    bool publisher_hash_checked_ = false;  ///< under take_order_
    /// Held from take to submit: the SHM and UDP receive threads both call on_data_available, and without it
    /// one could submit a later sample before the other submits the earlier one it took.
    std::mutex take_order_;
};

}  // namespace tgw::dds
