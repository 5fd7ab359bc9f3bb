// tm-basecamp echo against real Fast DDS publishers: the program as an operator runs it (--json, --count, over
// UDP unicast on loopback with --peer and --interface), each JSON line read back member by member; and the Echo
// class in-process for a type it has no IDL for.
#include <gtest/gtest.h>

#include <fstream>
#include <sstream>
#include <thread>

#include "AnnouncedTypesPubSubTypes.h"
#include "AnnouncedTypesTypeObject.h"
#include "GatewayStatusPubSubTypes.h"
#include "base/wan_address.hpp"
#include "basecamp/live/echo.hpp"
#include "test/integration/child_process.hpp"
#include "test/integration/dds_test_support.hpp"
#include "test/integration/error_log_counter.hpp"
#include "test/integration/json_reader.hpp"
#include "test/integration/opaque_type.hpp"

namespace tgw::test {
namespace {

using namespace std::chrono_literals;

class EchoTest : public ::testing::Test {
  protected:
    void SetUp() override {
        ErrorLogCounter::instance().take_errors();
        use_transports_in_process();
        domain_ = TestDomains::for_this_process().robot;
        topic_ = std::string("tgw_it/echo/") + ::testing::UnitTest::GetInstance()->current_test_info()->name();
        stderr_file_ = "/tmp/tgw_it_" + std::to_string(::getpid()) + "_echo.err";
        // The publisher on loopback UDP alone, announcing itself to the first participant port of the domain,
        // where the echo's participant (unicast, --peer 127.0.0.1) listens.
        fdds::DomainParticipantQos qos = TestParticipant::wan_qos(base::metatraffic_unicast_port(domain_, PUBLISHER_ID),
                                                                  base::metatraffic_unicast_port(domain_, 0));
        qos.name("test/echo publisher");
        qos.wire_protocol().participant_id = PUBLISHER_ID;
        publisher_ = std::make_unique<TestParticipant>(domain_, qos);
        ASSERT_TRUE(publisher_->ok());
    }

    void TearDown() override {
        publisher_.reset();
        std::remove(stderr_file_.c_str());
        const auto errors = ErrorLogCounter::instance().take_errors();
        std::string all;
        for (const auto& e : errors)
            all += e + "\n";
        EXPECT_TRUE(errors.empty()) << "Fast DDS logged errors:\n" << all;
    }

    /// tm-basecamp echo --json of the test's topic, for `count` samples, as an operator starts it.
    ChildProcess start_echo_json(int count) const {
        return ChildProcess(
            {TGW_BASECAMP_PROGRAM, "echo", topic_, "--domain", std::to_string(domain_), "--peer", "127.0.0.1",
             "--interface", "127.0.0.1", "--json", "--count", std::to_string(count), "--timeout", "40"},
            stderr_file_);
    }

    /// Whether the echo started and its reader matched the test's writer within 20 s.
    ::testing::AssertionResult echo_reader_matched(const ChildProcess& echo) const {
        if (!echo.started())
            return ::testing::AssertionFailure() << TGW_BASECAMP_PROGRAM << " did not start";
        if (!wait_until([&] { return matches_.matched.load() > 0; }, std::chrono::seconds(20)))
            return ::testing::AssertionFailure() << "the echo's reader never matched; its stderr:\n" << echo_stderr();
        return ::testing::AssertionSuccess();
    }

    std::string echo_stderr() const {
        std::ifstream in(stderr_file_);
        return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
    }

    /// The test's topic, of `type`, written reliably (keep last 10), its matches counted in matches_.
    fdds::DataWriter* reliable_writer(fdds::TopicDataType* type) {
        return publisher_->make_writer(topic_, fdds::TypeSupport(type), reliable_writer_qos(), &matches_);
    }

    fdds::DataWriterQos reliable_writer_qos() const {
        fdds::DataWriterQos qos = publisher_->default_writer_qos();
        qos.reliability().kind = fdds::RELIABLE_RELIABILITY_QOS;
        qos.history().kind = fdds::KEEP_LAST_HISTORY_QOS;
        qos.history().depth = 10;
        return qos;
    }

    // Above what Fast DDS assigns on its own, so the ports are this participant's.
    static constexpr std::uint32_t PUBLISHER_ID = 60;

    int domain_ = 0;
    std::string topic_;
    std::string stderr_file_;
    std::unique_ptr<TestParticipant> publisher_;
    MatchCounter matches_;
};

idl::GatewayStatus status_number(int i) {
    idl::GatewayStatus status;
    status.gateway_prefix({1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12});
    status.sent_ns(1'795'550'482'000'000'000ULL + static_cast<std::uint64_t>(i));
    status.sensed_rate_bps(20'000.5 + i);
    status.sensor("fixed:20000");
    status.sensor_detail("reading " + std::to_string(i) + " \"ok\"");
    status.status_period_s(1.5);
    status.budget_bps(19'000.25);
    status.unscheduled_wire_bytes(4096u + static_cast<unsigned>(i));
    status.log_samples(static_cast<unsigned>(i));
    status.matched_readers(-1);
    for (int j = 0; j <= i; ++j) {
        idl::TopicStatus topic;
        topic.name(std::string("telemetry/") + static_cast<char>('A' + j));
        topic.ttl_ms(1000u * static_cast<unsigned>(j + 1));
        topic.received(100u * static_cast<unsigned>(i) + static_cast<unsigned>(j));
        topic.matched_readers(j);
        status.topics().push_back(topic);
    }
    return status;
}

TEST_F(EchoTest, EchoJsonPrintsEachSampleOfAnIdlTypeFieldByField) {
    fdds::DataWriter* writer = reliable_writer(new idl::GatewayStatusPubSubType());
    ASSERT_NE(writer, nullptr);
    constexpr int SAMPLES = 3;
    ChildProcess echo = start_echo_json(SAMPLES);
    ASSERT_TRUE(echo_reader_matched(echo));

    for (int i = 0; i < SAMPLES; ++i) {
        idl::GatewayStatus status = status_number(i);
        const eprosima::fastrtps::Time_t stamp(1'795'550'482 + i, 123'000'000u + static_cast<std::uint32_t>(i));
        ASSERT_EQ(writer->write_w_timestamp(&status, fdds::HANDLE_NIL, stamp), ReturnCode_t::RETCODE_OK);
    }

    const Deadline deadline = std::chrono::steady_clock::now() + 20s;
    for (int i = 0; i < SAMPLES; ++i) {
        const std::optional<std::string> line = echo.read_line(deadline);
        ASSERT_TRUE(line.has_value()) << "sample " << i << " never came; stderr:\n" << echo_stderr();
        const std::optional<Json> sample = parse_json(*line);
        ASSERT_TRUE(sample.has_value()) << "not JSON: " << *line;
        EXPECT_EQ((*sample)["source_timestamp_ns"].as_uint(),
                  (1'795'550'482ULL + i) * 1'000'000'000ULL + 123'000'000ULL + static_cast<std::uint64_t>(i));
        // The key hash of a key of 12 bytes is the key itself, padded to 16.
        EXPECT_EQ((*sample)["instance"].text, "0102030405060708090a0b0c00000000");
        ASSERT_TRUE(sample->has("data")) << *line;
        const Json& data = (*sample)["data"];
        ASSERT_EQ(data["gateway_prefix"].items.size(), 12u) << *line;
        EXPECT_EQ(data["gateway_prefix"].items[11].as_uint(), 12u);
        EXPECT_EQ(data["sent_ns"].as_uint(), 1'795'550'482'000'000'000ULL + static_cast<std::uint64_t>(i));
        EXPECT_EQ(data["sensed_rate_bps"].as_double(), 20'000.5 + i);
        EXPECT_EQ(data["sensor"].text, "fixed:20000");
        EXPECT_EQ(data["sensor_detail"].text, "reading " + std::to_string(i) + " \"ok\"");
        EXPECT_EQ(data["status_period_s"].as_double(), 1.5);
        EXPECT_EQ(data["budget_bps"].as_double(), 19'000.25);
        EXPECT_EQ(data["unscheduled_wire_bytes"].as_uint(), 4096u + static_cast<unsigned>(i));
        EXPECT_EQ(data["log_samples"].as_uint(), static_cast<std::uint64_t>(i));
        EXPECT_EQ(data["matched_readers"].as_int(), -1);
        const Json& topics = data["topics"];
        ASSERT_EQ(topics.items.size(), static_cast<std::size_t>(i + 1)) << *line;
        for (int j = 0; j <= i; ++j) {
            const Json& topic = topics.items[static_cast<std::size_t>(j)];
            EXPECT_EQ(topic["name"].text, std::string("telemetry/") + static_cast<char>('A' + j));
            EXPECT_EQ(topic["ttl_ms"].as_uint(), 1000u * static_cast<unsigned>(j + 1));
            EXPECT_EQ(topic["received"].as_uint(), 100u * static_cast<unsigned>(i) + static_cast<unsigned>(j));
            EXPECT_EQ(topic["forwarded"].as_uint(), 0u);
            EXPECT_EQ(topic["matched_readers"].as_int(), j);
        }
    }
    EXPECT_EQ(echo.wait(std::chrono::steady_clock::now() + 15s), std::optional<int>(0)) << echo_stderr();
    EXPECT_NE(echo_stderr().find("of type tgw::idl::GatewayStatus"), std::string::npos) << echo_stderr();
}

// The publisher announces its type's XTypes TypeObject (fastddsgen -typeobject, the types registered); the echo,
// another process with no IDL of it, decodes every member from that alone.
TEST_F(EchoTest, EchoDecodesATypeFromTheTypeObjectItsPublisherAnnounced) {
    registerAnnouncedTypesTypes();
    fdds::DataWriter* writer = reliable_writer(new tgw_test::FlatReadingPubSubType());
    ASSERT_NE(writer, nullptr);
    constexpr int SAMPLES = 2;
    ChildProcess echo = start_echo_json(SAMPLES);
    ASSERT_TRUE(echo_reader_matched(echo));
    for (int i = 0; i < SAMPLES; ++i) {
        tgw_test::FlatReading reading;
        reading.sensor_id(100u + static_cast<unsigned>(i));
        reading.s64(-9'000'000'000'000LL);
        reading.f32(0.25F);
        reading.label(std::string(300, 'a' + static_cast<char>(i)));
        reading.unit("m/s");
        reading.history({1.5, -2.0});
        reading.grid({{{1, 2, 3}, {4, 5, i}}});
        ASSERT_TRUE(writer->write(&reading));
    }
    const Deadline deadline = std::chrono::steady_clock::now() + 20s;
    for (int i = 0; i < SAMPLES; ++i) {
        const std::optional<std::string> line = echo.read_line(deadline);
        ASSERT_TRUE(line.has_value()) << "sample " << i << " never came; stderr:\n" << echo_stderr();
        const std::optional<Json> sample = parse_json(*line);
        ASSERT_TRUE(sample.has_value()) << "not JSON: " << *line;
        ASSERT_TRUE(sample->has("data")) << *line << "\nstderr:\n" << echo_stderr();
        const Json& data = (*sample)["data"];
        EXPECT_EQ(data["sensor_id"].as_uint(), 100u + static_cast<unsigned>(i));
        EXPECT_EQ(data["s64"].as_int(), -9'000'000'000'000LL);
        EXPECT_EQ(data["f32"].as_double(), 0.25);
        EXPECT_EQ(data["label"].text, std::string(300, 'a' + static_cast<char>(i)));
        EXPECT_EQ(data["unit"].text, "m/s");
        ASSERT_EQ(data["history"].items.size(), 2u) << *line;
        EXPECT_EQ(data["history"].items[1].as_double(), -2.0);
        ASSERT_EQ(data["grid"].items.size(), 2u) << *line;
        ASSERT_EQ(data["grid"].items[1].items.size(), 3u) << *line;
        EXPECT_EQ(data["grid"].items[1].items[2].as_int(), i);
    }
    EXPECT_EQ(echo.wait(std::chrono::steady_clock::now() + 15s), std::optional<int>(0)) << echo_stderr();
    EXPECT_NE(echo_stderr().find("of type tgw_test::FlatReading, decoded with the XTypes TypeObject its publisher "
                                 "announced"),
              std::string::npos)
        << echo_stderr();
}

// A TypeObject refers to a nested struct, an enum and a typedef by hash only, and a Fast DDS 2.9 publisher answers
// no request for them by default: the echo says which member it cannot decode, and prints size and hex.
TEST_F(EchoTest, EchoSaysWhichMemberTheAnnouncedTypeObjectCannotDescribe) {
    registerAnnouncedTypesTypes();
    fdds::DataWriter* writer = reliable_writer(new tgw_test::RoverStatePubSubType());
    ASSERT_NE(writer, nullptr);
    ChildProcess echo = start_echo_json(1);
    ASSERT_TRUE(echo_reader_matched(echo));
    tgw_test::RoverState state;
    state.mode(tgw_test::DRIVING);
    ASSERT_TRUE(writer->write(&state));
    const std::optional<std::string> line = echo.read_line(std::chrono::steady_clock::now() + 20s);
    ASSERT_TRUE(line.has_value()) << "the sample never came; stderr:\n" << echo_stderr();
    const std::optional<Json> sample = parse_json(*line);
    ASSERT_TRUE(sample.has_value()) << "not JSON: " << *line;
    EXPECT_FALSE(sample->has("data")) << *line;
    EXPECT_GT((*sample)["size_bytes"].as_uint(), 0u) << *line;
    EXPECT_EQ(echo.wait(std::chrono::steady_clock::now() + 15s), std::optional<int>(0)) << echo_stderr();
    EXPECT_NE(echo_stderr().find("of type tgw_test::RoverState: its publisher's TypeObject: member 'reading' of "
                                 "tgw_test::RoverState: refers to a type its publisher did not announce (complete "
                                 "hash "),
              std::string::npos)
        << echo_stderr();
}

TEST_F(EchoTest, EchoPrintsSizeAndHexOfATypeItHasNoIdlFor) {
    fdds::DataWriter* writer = reliable_writer(new OpaqueBlobType());
    ASSERT_NE(writer, nullptr);
    types::TypeLibrary types;
    types.add_project_types();
    base::PeerTransport loopback;
    loopback.peers = {"127.0.0.1"};
    loopback.interface = "127.0.0.1";
    std::ostringstream out;
    std::atomic<bool> stop{false};
    std::uint64_t printed = 0;
    {
        basecamp::Echo sut(domain_, loopback, topic_, types, basecamp::SamplePrinter::Format::text, out);
        std::thread running([&] { printed = sut.run(2, std::chrono::seconds(40), stop); });
        const bool matched = wait_until([&] { return matches_.matched.load() > 0; }, 20s);
        for (std::uint32_t id = 1; matched && id <= 2; ++id) {
            OpaqueBlob blob;
            blob.id = id;
            blob.bytes = {0xca, 0xfe};
            EXPECT_TRUE(writer->write(&blob));
        }
        if (!matched)
            stop.store(true);
        running.join();
        ASSERT_TRUE(matched) << "the echo's reader never matched";
        EXPECT_EQ(sut.type_name(), OpaqueBlobType::TYPE_NAME);
    }
    ASSERT_EQ(printed, 2u);
    // Each sample: the source time, why it is not decoded, then its bytes as they came: CDR_LE, the id, a
    // sequence of 2, and the 2 bytes RTPS pads serialized data with to a multiple of 4.
    const std::string text = out.str();
    EXPECT_NE(text.find("# cannot decode: no IDL for the type test_only::OpaqueBlob\n"
                        "size_bytes: 16\n"
                        "hex: 000100000100000002000000cafe0000\n"
                        "---\n"),
              std::string::npos)
        << text;
    EXPECT_NE(text.find("hex: 000100000200000002000000cafe0000\n---\n"), std::string::npos) << text;
    EXPECT_EQ(text.rfind("# source_timestamp: ", 0), 0u) << text;
}

}  // namespace
}  // namespace tgw::test
