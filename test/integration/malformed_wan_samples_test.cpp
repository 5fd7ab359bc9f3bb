// Malformed samples on the WAN topics the gateway reads: any participant on the WAN domain can write them, and
// Fast-CDR throws on some (an unknown encapsulation), which Fast DDS's take() lets through. The gateway must
// refuse them and go on.
#include <gtest/gtest.h>

#include <cstdint>
#include <vector>

#include "ReceiverReportPubSubTypes.h"
#include "base/wan_address.hpp"
#include "test/integration/gateway_fixture.hpp"
#include "test/integration/raw_sample_type.hpp"
#include "wire/receiver_report_topic.hpp"

namespace tgw::test {
namespace {

class MalformedWanSamplesTest : public GatewayIntegrationTest {};

std::vector<std::uint8_t> good_report(const eprosima::fastrtps::rtps::GuidPrefix_t& gateway, std::uint64_t received) {
    idl::ReceiverReport report;
    std::copy(std::begin(gateway.value), std::end(gateway.value), report.gateway_prefix().begin());
    report.received_samples(received);
    report.received_bytes(received * 100);
    idl::ReceiverReportPubSubType type;
    eprosima::fastrtps::rtps::SerializedPayload_t payload(type.m_typeSize);
    type.serialize(&report, &payload);
    return {payload.data, payload.data + payload.length};
}

TEST_F(MalformedWanSamplesTest, AMalformedReceiverReportIsRefusedAndTheNextGoodOneTaken) {
    GatewayConfig c = config();
    c.receiver_reports = true;
    start_gateway(c);
    TestParticipant stranger(domains_.wan, TestParticipant::wan_qos(base::metatraffic_unicast_port(domains_.wan, 62),
                                                                    domains_.gateway_wan_port));
    ASSERT_TRUE(stranger.ok());
    auto& matches = listener<MatchCounter>();
    fdds::DataWriter* writer = stranger.make_writer(
        wire::RECEIVER_REPORT_TOPIC, fdds::TypeSupport(new RawSampleType("tgw::idl::ReceiverReport", true)),
        stranger.default_writer_qos(), &matches);
    ASSERT_NE(writer, nullptr);
    ASSERT_TRUE(wait_until([&] { return matches.matched > 0; }, MATCH_TIMEOUT)) << "the gateway's reader never matched";

    const std::vector<std::vector<std::uint8_t>> malformed = {
        {0x00, 0x07, 0x00, 0x00, 1, 2, 3, 4},  // an encapsulation that does not exist: Fast-CDR throws
        {0x05, 0x01, 0x00, 0x00},              // a first byte that must be zero: Fast-CDR throws
        {0x00, 0x01, 0x00, 0x00, 1, 2, 3},     // truncated
        {},                                    // empty
    };
    const auto prefix = gateway_->wan_guid_prefix();
    for (std::uint64_t round = 1; round <= 3; ++round) {
        std::uint8_t key = 1;
        for (const auto& bytes : malformed) {
            RawSample bad{bytes, key++};
            ASSERT_TRUE(writer->write(&bad));
        }
        RawSample good{good_report(prefix, round), 0};
        ASSERT_TRUE(wait_until([&] {
            writer->write(&good);  // best effort: again until the gateway has taken it
            const auto report = gateway_->receiver_report();
            return report && report->received_samples == round;
        })) << "round "
            << round << ": the gateway never took the good report after the malformed ones";
    }
    EXPECT_EQ(gateway_->receiver_report()->received_bytes, 300u);
    // Fast DDS logs each sample it could not deserialize; that is the only error expected here.
    for (const std::string& error : ErrorLogCounter::instance().take_errors()) {
        EXPECT_NE(error.find("deserializ"), std::string::npos) << error;
    }
}

}  // namespace
}  // namespace tgw::test
