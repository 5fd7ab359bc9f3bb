#include "passthrough/passthrough_qos.hpp"

#include "passthrough/dds_time.hpp"

namespace tgw::passthrough {

namespace fdds = eprosima::fastdds::dds;

namespace {

// Room for bursts between two listener calls; the listener takes every sample as it arrives.
constexpr std::int32_t READER_HISTORY_DEPTH = 1000;
// A reliable lane keeps what a reader may still ask to be repaired: KEEP_LAST per instance, and a Lifespan
// removes what is stale, so a repair of a sample past its deadline is never sent.
constexpr std::int32_t RELIABLE_WRITER_HISTORY_DEPTH = 64;
// Fast DDS sizes a keyed KEEP_LAST history as depth x max_instances, so "unlimited" (-1) is not an option.
constexpr std::int32_t MAX_INSTANCES = 65536;

eprosima::fastrtps::rtps::MemoryManagementPolicy_t payload_policy(bool keyed) {
    return keyed ? eprosima::fastrtps::rtps::PREALLOCATED_WITH_REALLOC_MEMORY_MODE
                 : eprosima::fastrtps::rtps::DYNAMIC_REUSABLE_MEMORY_MODE;
}

}  // namespace

fdds::DataReaderQos passthrough_reader_qos(fdds::DataReaderQos base, const OfferedQos& offer, bool keyed) {
    // expects_inline_qos only for keyed Fast DDS writers (OfferedQos::needs_inline_key_hash); the instance
    // comes from SampleInfo.
    offer.apply_to_robot_reader(base);
    base.history().kind = fdds::KEEP_LAST_HISTORY_QOS;
    base.history().depth = READER_HISTORY_DEPTH;
    base.resource_limits().max_samples_per_instance = READER_HISTORY_DEPTH;
    base.resource_limits().max_samples = fdds::LENGTH_UNLIMITED;
    base.resource_limits().max_instances = MAX_INSTANCES;
    base.resource_limits().allocated_samples = 16;
    base.endpoint().history_memory_policy = payload_policy(keyed);
    base.data_sharing().off();
    return base;
}

fdds::DataWriterQos passthrough_writer_qos(fdds::DataWriterQos base, const OfferedQos& offer, bool keyed,
                                           std::optional<base::Duration> lifespan) {
    offer.apply_to_wan_writer(base);
    base.history().kind = fdds::KEEP_LAST_HISTORY_QOS;
    base.history().depth = offer.reliable && !offer.transient_local ? RELIABLE_WRITER_HISTORY_DEPTH : 1;
    base.resource_limits().max_samples = fdds::LENGTH_UNLIMITED;
    base.resource_limits().max_instances = MAX_INSTANCES;
    base.resource_limits().max_samples_per_instance = base.history().depth;
    base.lifespan().duration = lifespan ? to_dds_duration(*lifespan) : eprosima::fastrtps::c_TimeInfinite;
    base.endpoint().history_memory_policy = payload_policy(keyed);
    base.data_sharing().off();
    // A publisher's dispose arrives as a dispose and is passed on as one; an unregister must stay an unregister,
    // not become a dispose (Fast DDS's default for unregister_instance).
    base.writer_data_lifecycle().autodispose_unregistered_instances = false;
    return base;
}

}  // namespace tgw::passthrough
