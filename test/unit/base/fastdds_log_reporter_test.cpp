#include "base/fastdds_log_reporter.hpp"

#include <gtest/gtest.h>

#include <memory>
#include <sstream>

#include <fastdds/rtps/transport/UDPv4TransportDescriptor.h>
#include <fastdds/dds/domain/DomainParticipant.hpp>
#include <fastdds/dds/domain/DomainParticipantFactory.hpp>

namespace tgw::base {
namespace {

using eprosima::fastdds::dds::Log;

Log::Entry entry(const std::string& message, const char* category = "TRANSPORT", Log::Kind kind = Log::Kind::Error) {
    Log::Entry made;
    made.message = message;
    made.context = {"UDPv4Transport.cpp", 1, "filter", category};
    made.kind = kind;
    return made;
}

TEST(PlainLineTest, DropsTerminalColourCodesAndLineBreaks) {
    EXPECT_EQ(plain_line("\x1b[1;31mbound\x1b[0m to\n\tnothing \n"), "bound to nothing");
    EXPECT_EQ(plain_line("plain"), "plain");
    EXPECT_EQ(plain_line("\x1b[37;1m"), "");
}

class FastDdsLogReporterTest : public ::testing::Test {
  protected:
    std::ostringstream out;
    SteadyTime now{};
    FastDdsLogReporter sut{"telemetry-gateway", out, std::chrono::seconds(10), [this] { return now; }};
};

TEST_F(FastDdsLogReporterTest, PrintsOneLineNamingTheProgramTheCategoryAndWhatToDo) {
    sut.Consume(entry("All whitelist interfaces were filtered out"));
    const std::string line = out.str();
    EXPECT_EQ(line.rfind("telemetry-gateway: Fast DDS error (TRANSPORT): All whitelist interfaces were filtered out; "
                         "the interface this participant was bound to is down",
                         0),
              0u)
        << line;
    EXPECT_EQ(line.find('\x1b'), std::string::npos);
    EXPECT_EQ(line.find('\n'), line.size() - 1);
}

TEST_F(FastDdsLogReporterTest, AMessageWeDoNotKnowIsPrintedAsItIs) {
    sut.Consume(entry("\x1b[31mSomething new\x1b[0m", "RTPS_WRITER", Log::Kind::Warning));
    EXPECT_EQ(out.str(), "telemetry-gateway: Fast DDS warning (RTPS_WRITER): Something new\n");
}

TEST_F(FastDdsLogReporterTest, ARepeatWithinTheQuietTimeIsCountedAndToldWithTheNextLine) {
    sut.Consume(entry("Error sending change"));
    now += std::chrono::seconds(1);
    sut.Consume(entry("Error sending change"));
    sut.Consume(entry("Error sending change"));
    sut.Consume(entry("Something else"));
    now += std::chrono::seconds(10);
    sut.Consume(entry("Error sending change"));
    EXPECT_EQ(
        out.str(),
        "telemetry-gateway: Fast DDS error (TRANSPORT): Error sending change\n"
        "telemetry-gateway: Fast DDS error (TRANSPORT): Something else\n"
        "telemetry-gateway: Fast DDS error (TRANSPORT): Error sending change [2 more since the last such line]\n");
}

// The message as Fast DDS 2.9 itself logs it: a participant bound to an address no interface of this host has.
TEST(FastDdsLogReporterParticipantTest, FastDdsOwnErrorReachesTheReporterAsOneLine) {
    std::ostringstream out;
    Log::ClearConsumers();
    Log::RegisterConsumer(std::make_unique<FastDdsLogReporter>("tm-basecamp", out));
    auto* factory = eprosima::fastdds::dds::DomainParticipantFactory::get_instance();
    auto qos = factory->get_default_participant_qos();
    auto udp = std::make_shared<eprosima::fastdds::rtps::UDPv4TransportDescriptor>();
    udp->interfaceWhiteList.push_back("192.0.2.77");  // TEST-NET-1: on no interface here
    qos.transport().use_builtin_transports = false;
    qos.transport().user_transports.push_back(udp);
    auto* participant = factory->create_participant(231, qos);
    Log::Flush();
    if (participant != nullptr)
        factory->delete_participant(participant);
    Log::Reset();  // Fast DDS's own consumer again, for what runs after
    const std::string text = out.str();
    EXPECT_NE(text.find("tm-basecamp: Fast DDS error (TRANSPORT): All whitelist interfaces were filtered out; "),
              std::string::npos)
        << text;
    EXPECT_EQ(text.find('\x1b'), std::string::npos) << text;
}

}  // namespace
}  // namespace tgw::base
