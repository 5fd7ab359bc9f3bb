// One sample of each of the project's IDL types, serialized by fastddsgen's code, written as a recording
// (SampleStore, as tm-basecamp record writes one) and, beside it, the values of their members as JSON: what an
// independent reader must decode from the MCAP export's omgidl schemas (test/readers/check_mcap.mjs --expect).
//
//   project_type_samples RECORDING.db EXPECTED.json
#include <cstdio>
#include <fstream>
#include <string>
#include <vector>

#include "GatewayStatus.h"
#include "KeyedReading.h"
#include "PaperWorkload.h"
#include "ReceiverReport.h"
#include "RobotPose.h"
#include "RosString.h"

#include "basecamp/recording/sample_store.hpp"
#include "test/unit/types/cdr_test_payloads.hpp"

namespace {

constexpr std::int64_t SOURCE_NS = 1'795'560'000'000'000'000;

}  // namespace

int main(int argc, char** argv) {
    if (argc != 3) {
        std::fprintf(stderr, "usage: %s RECORDING.db EXPECTED.json\n", argv[0]);
        return 2;
    }
    std::vector<tgw::basecamp::SampleRecord> samples;
    const auto add = [&](const std::string& topic, const std::string& type, std::vector<std::uint8_t> payload) {
        tgw::basecamp::SampleRecord s;
        s.topic = topic;
        s.type_name = type;
        s.payload = std::move(payload);
        s.source_ns = SOURCE_NS + static_cast<std::int64_t>(samples.size());
        s.receive_ns = s.source_ns + 40'000'000;
        samples.push_back(std::move(s));
    };

    tgw::idl::PaperMessage paper;
    paper.generated_ns(SOURCE_NS);
    paper.sequence_number(7);
    paper.data({0, 1, 2, 250});
    add("types/paper", "tgw::idl::PaperMessage",
        tgw::test::fastcdr_payload(paper, eprosima::fastcdr::Cdr::LITTLE_ENDIANNESS));

    std_msgs::msg::dds_::String_ text;
    text.data("hazard ahead: \"rock\"");
    add("rt/chatter", "std_msgs::msg::dds_::String_",
        tgw::test::fastcdr_payload(text, eprosima::fastcdr::Cdr::LITTLE_ENDIANNESS));

    tgw::idl::KeyedReading keyed;
    keyed.sensor_id(42);
    keyed.value(-273.15);
    keyed.label("left wheel");
    add("types/keyed", "tgw::idl::KeyedReading",
        tgw::test::fastcdr_payload(keyed, eprosima::fastcdr::Cdr::LITTLE_ENDIANNESS));

    tgw::idl::ReceiverReport report;
    report.gateway_prefix({1, 15, 2, 3, 4, 5, 6, 7, 8, 9, 10, 255});
    report.received_samples(1234);
    report.received_bytes(98'765);
    report.lost_samples(3);
    report.sent_ns(1'795'560'000'123'456'789ULL);
    add("types/report", "tgw::idl::ReceiverReport",
        tgw::test::fastcdr_payload(report, eprosima::fastcdr::Cdr::LITTLE_ENDIANNESS));

    tgw::idl::RobotPose pose;
    pose.x(120.5);
    pose.y(-3.25);
    pose.heading_rad(1.5);
    add("robot/pose", "tgw::idl::RobotPose",
        tgw::test::fastcdr_payload(pose, eprosima::fastcdr::Cdr::LITTLE_ENDIANNESS));

    tgw::idl::GatewayStatus status;
    status.gateway_prefix({1, 15, 2, 3, 4, 5, 6, 7, 8, 9, 10, 255});
    status.robot_name("rover1");
    status.sent_ns(1'795'560'000'000'000'000ULL);
    status.sensed_rate_bps(20'000.5);
    status.compact_wan(true);
    status.sensor("qdisc:veth0");
    status.sensor_detail("tbf rate 20kbit");
    status.status_period_s(1.0);
    status.budget_bps(19'000.25);
    status.delivered_cap_bps(18'000);
    status.unscheduled_wire_bytes(4096);
    status.log_samples(17);
    status.matched_readers(2);
    tgw::idl::TopicStatus topic;
    topic.name("telemetry/A");
    topic.ttl_ms(1000);
    topic.received(300);
    topic.forwarded(298);
    topic.forwarded_bytes(298 * 64);
    topic.expired(2);
    topic.matched_readers(1);
    topic.active_ms(60'000);
    status.topics().push_back(topic);
    status.uplink_topics({"rt/rover1/cmd_vel"});
    status.uplink_charged(true);
    status.uplink_wire_bytes(9680);
    status.backfill_rows(120);
    status.backfill_bytes(90'000);
    status.backfill_oldest_ns(1'795'559'900'000'000'000);
    status.backfill_sent(40);
    status.backfill_acknowledged(35);
    add("tgw/status", "tgw::idl::GatewayStatus",
        tgw::test::fastcdr_payload(status, eprosima::fastcdr::Cdr::LITTLE_ENDIANNESS));

    {
        tgw::basecamp::SampleStore store(argv[1], "RECORDING.db", 10);
        for (const auto& s : samples)
            store.add(s);
        store.flush();
    }

    // 64-bit integers as strings: JSON numbers lose them past 2^53, and the readers give them as BigInt.
    std::ofstream out(argv[2]);
    out << R"({
  "types/paper": {"generated_ns": "1795560000000000000", "sequence_number": 7, "data": [0, 1, 2, 250]},
  "rt/chatter": {"data": "hazard ahead: \"rock\""},
  "types/keyed": {"sensor_id": 42, "value": -273.15, "label": "left wheel"},
  "types/report": {"gateway_prefix": [1, 15, 2, 3, 4, 5, 6, 7, 8, 9, 10, 255], "received_samples": "1234",
                   "received_bytes": "98765", "lost_samples": "3", "sent_ns": "1795560000123456789"},
  "robot/pose": {"x": 120.5, "y": -3.25, "heading_rad": 1.5},
  "tgw/status": {"gateway_prefix": [1, 15, 2, 3, 4, 5, 6, 7, 8, 9, 10, 255], "robot_name": "rover1",
                 "sent_ns": "1795560000000000000", "sensed_rate_bps": 20000.5, "compact_wan": true, "sensor": "qdisc:veth0", "sensor_detail": "tbf rate 20kbit",
                 "status_period_s": 1, "budget_bps": 19000.25, "delivered_cap_bps": 18000,
                 "unscheduled_wire_bytes": "4096", "log_samples": "17", "matched_readers": 2,
                 "topics": [{"name": "telemetry/A", "ttl_ms": 1000, "queued_samples": 0, "queued_bytes": "0",
                             "received": "300", "forwarded": "298", "forwarded_wire_bytes": "0", "forwarded_bytes": "19072",
                             "expired": "2",
                             "doomed": "0", "evicted": "0", "oversize": "0", "shutdown": "0", "write_failed": "0",
                             "no_reader": "0", "rate_capped": "0", "superseded": "0",
                             "matched_readers": 1, "active_ms": 60000}],
                 "uplink_topics": ["rt/rover1/cmd_vel"], "uplink_charged": true, "uplink_wire_bytes": "9680",
                 "backfill_rows": "120", "backfill_bytes": "90000", "backfill_oldest_ns": "1795559900000000000",
                 "backfill_sent": "40", "backfill_acknowledged": "35"}
}
)";
    return out ? 0 : 1;
}
