#include "passthrough/offered_qos.hpp"

#include <algorithm>
#include <sstream>

#include "passthrough/dds_time.hpp"

namespace tgw::passthrough {

namespace fdds = eprosima::fastdds::dds;

namespace {

eprosima::fastrtps::Duration_t to_dds(const std::optional<base::Duration>& d) {
    return d ? to_dds_duration(*d) : eprosima::fastrtps::c_TimeInfinite;
}

fdds::LivelinessQosPolicyKind to_dds(OfferedQos::Liveliness kind) {
    switch (kind) {
        case OfferedQos::Liveliness::manual_by_participant:
            return fdds::MANUAL_BY_PARTICIPANT_LIVELINESS_QOS;
        case OfferedQos::Liveliness::manual_by_topic:
            return fdds::MANUAL_BY_TOPIC_LIVELINESS_QOS;
        case OfferedQos::Liveliness::automatic:
            break;
    }
    return fdds::AUTOMATIC_LIVELINESS_QOS;
}

std::string seconds_text(base::Duration d) {
    std::ostringstream out;
    out << std::chrono::duration<double>(d).count() << 's';
    return out.str();
}

}  // namespace

OfferedQos OfferedQos::from_writer(const fdds::WriterQos& qos, bool fast_dds_keyed) {
    OfferedQos offer;
    offer.needs_inline_key_hash = fast_dds_keyed;
    offer.reliable = qos.m_reliability.kind == fdds::RELIABLE_RELIABILITY_QOS;
    offer.transient_local = qos.m_durability.kind != fdds::VOLATILE_DURABILITY_QOS;
    for (const std::string& name : qos.m_partition.names()) {
        offer.partitions.push_back(name);
    }
    std::sort(offer.partitions.begin(), offer.partitions.end());
    offer.partitions.erase(std::unique(offer.partitions.begin(), offer.partitions.end()), offer.partitions.end());
    offer.deadline = to_duration(qos.m_deadline.period);
    switch (qos.m_liveliness.kind) {
        case fdds::MANUAL_BY_PARTICIPANT_LIVELINESS_QOS:
            offer.liveliness = Liveliness::manual_by_participant;
            break;
        case fdds::MANUAL_BY_TOPIC_LIVELINESS_QOS:
            offer.liveliness = Liveliness::manual_by_topic;
            break;
        default:
            offer.liveliness = Liveliness::automatic;
    }
    offer.liveliness_lease = to_duration(qos.m_liveliness.lease_duration);
    offer.exclusive_ownership = qos.m_ownership.kind == fdds::EXCLUSIVE_OWNERSHIP_QOS;
    offer.ownership_strength = offer.exclusive_ownership ? qos.m_ownershipStrength.value : 0;
    const auto& representation = qos.representation.m_value;
    offer.xcdr2 = !representation.empty() && representation.front() == fdds::XCDR2_DATA_REPRESENTATION;
    return offer;
}

void OfferedQos::apply_to_robot_reader(fdds::DataReaderQos& reader) const {
    // Asking for exactly the offer matches every publisher of this lane; deadline and liveliness stay at the
    // weakest request (infinite), which any offer meets.
    reader.reliability().kind = reliable ? fdds::RELIABLE_RELIABILITY_QOS : fdds::BEST_EFFORT_RELIABILITY_QOS;
    reader.durability().kind = transient_local ? fdds::TRANSIENT_LOCAL_DURABILITY_QOS : fdds::VOLATILE_DURABILITY_QOS;
    reader.ownership().kind = exclusive_ownership ? fdds::EXCLUSIVE_OWNERSHIP_QOS : fdds::SHARED_OWNERSHIP_QOS;
    // Either representation: the payload passes through as it came.
    reader.type_consistency().representation.m_value = {fdds::XCDR_DATA_REPRESENTATION,
                                                        fdds::XCDR2_DATA_REPRESENTATION};
    reader.expects_inline_qos(needs_inline_key_hash);
}

void OfferedQos::apply_to_wan_writer(fdds::DataWriterQos& writer) const {
    writer.reliability().kind = reliable ? fdds::RELIABLE_RELIABILITY_QOS : fdds::BEST_EFFORT_RELIABILITY_QOS;
    writer.durability().kind = transient_local ? fdds::TRANSIENT_LOCAL_DURABILITY_QOS : fdds::VOLATILE_DURABILITY_QOS;
    writer.deadline().period = to_dds(deadline);
    writer.liveliness().kind = to_dds(liveliness);
    writer.liveliness().lease_duration = to_dds(liveliness_lease);
    if (liveliness_lease) {
        // Fast DDS asserts at this period; the RTPS default is shorter than the lease, as it must be.
        writer.liveliness().announcement_period = to_dds_duration(*liveliness_lease * 3 / 4);
    }
    writer.ownership().kind = exclusive_ownership ? fdds::EXCLUSIVE_OWNERSHIP_QOS : fdds::SHARED_OWNERSHIP_QOS;
    writer.ownership_strength().value = ownership_strength;
    writer.representation().m_value = {xcdr2 ? fdds::XCDR2_DATA_REPRESENTATION : fdds::XCDR_DATA_REPRESENTATION};
}

fdds::PartitionQosPolicy OfferedQos::partition_policy() const {
    fdds::PartitionQosPolicy policy;
    for (const std::string& name : partitions) {
        policy.push_back(name.c_str());
    }
    return policy;
}

std::string OfferedQos::describe() const {
    std::ostringstream out;
    out << (reliable ? "reliable" : "best-effort") << ' ' << (transient_local ? "transient-local" : "volatile");
    if (!partitions.empty()) {
        out << " partitions=";
        for (std::size_t i = 0; i < partitions.size(); ++i) {
            out << (i ? "," : "") << partitions[i];
        }
    }
    if (deadline) {
        out << " deadline=" << seconds_text(*deadline);
    }
    if (liveliness != Liveliness::automatic) {
        out << (liveliness == Liveliness::manual_by_topic ? " liveliness=manual-by-topic"
                                                          : " liveliness=manual-by-participant");
    }
    if (liveliness_lease) {
        out << " lease=" << seconds_text(*liveliness_lease);
    }
    if (exclusive_ownership) {
        out << " exclusive strength=" << ownership_strength;
    }
    if (xcdr2) {
        out << " xcdr2";
    }
    return out.str();
}

}  // namespace tgw::passthrough
