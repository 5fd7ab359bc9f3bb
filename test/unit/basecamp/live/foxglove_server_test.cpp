// The Foxglove server's start: a free port when asked for 0, and a port that is taken named in a ConfigError. What
// it serves is checked with Foxglove's own client (foxglove_live_view).
#include <gtest/gtest.h>

#include "basecamp/live/foxglove_server.hpp"
#include "test/fakes/config_error_of.hpp"

namespace tgw::test {
namespace {

TEST(FoxgloveServerTest, PortZeroListensOnAFreePortAndATakenPortIsAConfigError) {
    basecamp::FoxgloveServer first(0, types::TypeLibrary{}, "--foxglove-port");
    ASSERT_GT(first.port(), 0);
    EXPECT_EQ(first.clients(), 0u);
    const std::string taken = std::to_string(first.port());
    EXPECT_EQ(config_error_of([&] {
                  basecamp::FoxgloveServer second(first.port(), {}, "--foxglove-port");
              }).rfind("--foxglove-port: cannot listen on port " + taken + ": ", 0),
              0u);
}

TEST(FoxgloveServerTest, SamplesWithNoClientCostNothingAndStopIsClean) {
    basecamp::FoxgloveServer server(0, types::TypeLibrary{}, "--foxglove-port");
    basecamp::SampleRecord sample;
    sample.topic = "telemetry/A";
    sample.type_name = "tgw::idl::PaperMessage";
    sample.payload = {0, 1, 0, 0};
    for (int i = 0; i < 1000; ++i)
        server.add(sample);
    EXPECT_EQ(server.messages_sent(), 0u);
}

}  // namespace
}  // namespace tgw::test
