#include "passthrough/offered_qos.hpp"

#include <gtest/gtest.h>

namespace tgw::passthrough {
namespace {

namespace fdds = eprosima::fastdds::dds;
using namespace std::chrono_literals;

/// A discovered writer's QoS as SEDP delivers it: the DDS defaults until a test says otherwise.
fdds::WriterQos writer() {
    fdds::WriterQos q;
    q.m_reliability.kind = fdds::RELIABLE_RELIABILITY_QOS;
    q.m_durability.kind = fdds::VOLATILE_DURABILITY_QOS;
    return q;
}

TEST(OfferedQosTest, ReadsEveryPolicyThatDecidesMatching) {
    fdds::WriterQos q = writer();
    q.m_durability.kind = fdds::TRANSIENT_DURABILITY_QOS;
    q.m_partition.push_back("site7");
    q.m_partition.push_back("alpha");
    q.m_deadline.period = eprosima::fastrtps::Duration_t(0, 500'000'000);
    q.m_liveliness.kind = fdds::MANUAL_BY_TOPIC_LIVELINESS_QOS;
    q.m_liveliness.lease_duration = eprosima::fastrtps::Duration_t(2, 0);
    q.m_ownership.kind = fdds::EXCLUSIVE_OWNERSHIP_QOS;
    q.m_ownershipStrength.value = 9;
    q.representation.m_value = {fdds::XCDR2_DATA_REPRESENTATION};

    const OfferedQos sut = OfferedQos::from_writer(q, true);
    EXPECT_TRUE(sut.reliable);
    EXPECT_TRUE(sut.transient_local) << "TRANSIENT is served as TRANSIENT_LOCAL";
    EXPECT_EQ(sut.partitions, (std::vector<std::string>{"alpha", "site7"}));
    EXPECT_EQ(sut.deadline, base::Duration(500ms));
    EXPECT_EQ(sut.liveliness, OfferedQos::Liveliness::manual_by_topic);
    EXPECT_EQ(sut.liveliness_lease, base::Duration(2s));
    EXPECT_TRUE(sut.exclusive_ownership);
    EXPECT_EQ(sut.ownership_strength, 9u);
    EXPECT_TRUE(sut.xcdr2);
    EXPECT_TRUE(sut.needs_inline_key_hash);
    EXPECT_EQ(sut.describe(),
              "reliable transient-local partitions=alpha,site7 deadline=0.5s liveliness=manual-by-topic lease=2s "
              "exclusive strength=9 xcdr2");
}

TEST(OfferedQosTest, PublishersThatOfferTheSameShareALane) {
    fdds::WriterQos a = writer();
    a.m_partition.push_back("x");
    a.m_partition.push_back("y");
    fdds::WriterQos b = writer();
    b.m_partition.push_back("y");
    b.m_partition.push_back("x");
    b.m_lifespan.duration = eprosima::fastrtps::Duration_t(3, 0);  // the gateway's own: not part of the offer
    EXPECT_EQ(OfferedQos::from_writer(a), OfferedQos::from_writer(b));
    b.m_reliability.kind = fdds::BEST_EFFORT_RELIABILITY_QOS;
    EXPECT_NE(OfferedQos::from_writer(a), OfferedQos::from_writer(b));
}

TEST(OfferedQosTest, TheWanWriterOffersWhatThePublisherOffered) {
    fdds::WriterQos q = writer();
    q.m_durability.kind = fdds::TRANSIENT_LOCAL_DURABILITY_QOS;
    q.m_ownership.kind = fdds::EXCLUSIVE_OWNERSHIP_QOS;
    q.m_ownershipStrength.value = 4;
    q.m_deadline.period = eprosima::fastrtps::Duration_t(1, 0);
    const OfferedQos sut = OfferedQos::from_writer(q);

    fdds::DataWriterQos w;
    w.reliability().kind = fdds::BEST_EFFORT_RELIABILITY_QOS;
    sut.apply_to_wan_writer(w);
    EXPECT_EQ(w.reliability().kind, fdds::RELIABLE_RELIABILITY_QOS);
    EXPECT_EQ(w.durability().kind, fdds::TRANSIENT_LOCAL_DURABILITY_QOS);
    EXPECT_EQ(w.ownership().kind, fdds::EXCLUSIVE_OWNERSHIP_QOS);
    EXPECT_EQ(w.ownership_strength().value, 4u);
    EXPECT_EQ(w.deadline().period, eprosima::fastrtps::Duration_t(1, 0));
    EXPECT_EQ(w.representation().m_value, std::vector<fdds::DataRepresentationId_t>{fdds::XCDR_DATA_REPRESENTATION});
}

TEST(OfferedQosTest, TheRobotReaderAsksForNoMoreThanTheOffer) {
    fdds::WriterQos q = writer();
    q.m_reliability.kind = fdds::BEST_EFFORT_RELIABILITY_QOS;
    const OfferedQos sut = OfferedQos::from_writer(q);
    fdds::DataReaderQos r;
    r.reliability().kind = fdds::RELIABLE_RELIABILITY_QOS;
    r.durability().kind = fdds::TRANSIENT_LOCAL_DURABILITY_QOS;
    sut.apply_to_robot_reader(r);
    EXPECT_EQ(r.reliability().kind, fdds::BEST_EFFORT_RELIABILITY_QOS);
    EXPECT_EQ(r.durability().kind, fdds::VOLATILE_DURABILITY_QOS);
    EXPECT_FALSE(r.expects_inline_qos()) << "Cyclone refuses readers that expect inline QoS";
    EXPECT_EQ(r.type_consistency().representation.m_value.size(), 2u) << "XCDR1 and XCDR2 both pass through";
}

}  // namespace
}  // namespace tgw::passthrough
