// The link-quality map from a recording written as tm-basecamp record writes one: a pose topic along a known
// path, statuses whose sensed rate falls with x, and drops counted in them (or, from a mission archive, sample by
// sample). The model is checked by value; the picture by the colours at the path's two ends.
#include <gtest/gtest.h>

#include <cairo.h>
#include <unistd.h>

#include <cmath>

#include "GatewayStatus.h"
#include "RobotPose.h"

#include "basecamp/analysis/link_map.hpp"
#include "basecamp/analysis/link_map_render.hpp"
#include "basecamp/recording/recording_reader.hpp"
#include "test/fakes/config_error_of.hpp"
#include "test/unit/basecamp/recording_file.hpp"
#include "test/unit/types/cdr_test_payloads.hpp"

namespace tgw::test {
namespace {

constexpr std::int64_t SECOND = 1'000'000'000;
constexpr std::int64_t START = 1'795'000'000 * SECOND;

basecamp::SampleRecord sample_of(const std::string& topic, const std::string& type, std::vector<std::uint8_t> bytes,
                                 std::int64_t source_ns) {
    basecamp::SampleRecord s;
    s.topic = topic;
    s.type_name = type;
    s.payload = std::move(bytes);
    s.source_ns = source_ns;
    s.receive_ns = source_ns + SECOND / 20;
    return s;
}

/// 0 to 100 m east in 10 s at 5 Hz, then 50 m north; a status a second whose rate falls from 70 to 10 kbit/s
/// along x, and 3 samples logged on the robot between the statuses of seconds 8 and 9 (near x = 90).
std::vector<basecamp::SampleRecord> mission() {
    std::vector<basecamp::SampleRecord> samples;
    for (int i = 0; i <= 75; ++i) {
        idl::RobotPose pose;
        const double t = i / 5.0;
        pose.x(std::min(t, 10.0) * 10);
        pose.y(t > 10 ? (t - 10) * 10 : 0);
        samples.push_back(sample_of("robot/pose", "tgw::idl::RobotPose",
                                    fastcdr_payload(pose, eprosima::fastcdr::Cdr::LITTLE_ENDIANNESS),
                                    START + i * SECOND / 5));
    }
    for (int s = 0; s <= 15; ++s) {
        idl::GatewayStatus status;
        status.sensor("fixed");
        status.sensed_rate_bps(70'000 - 6'000 * std::min(s, 10));
        idl::TopicStatus topic;
        topic.name("telemetry/D");
        topic.expired(s >= 9 ? 3 : 0);
        status.topics().push_back(topic);
        samples.push_back(sample_of("tgw/status", "tgw::idl::GatewayStatus",
                                    fastcdr_payload(status, eprosima::fastcdr::Cdr::LITTLE_ENDIANNESS),
                                    START + s * SECOND));
    }
    return samples;
}

class LinkMapTest : public ::testing::Test {
  protected:
    void SetUp() override {
        const std::string prefix = "/tmp/tgw_linkmap_" + std::to_string(::getpid()) + "_" +
                                   ::testing::UnitTest::GetInstance()->current_test_info()->name();
        recording_ = prefix + ".db";
        png_ = prefix + ".png";
    }
    void TearDown() override {
        for (const std::string& f : {recording_, recording_ + "-wal", recording_ + "-shm", png_})
            std::remove(f.c_str());
    }

    basecamp::LinkMap build(const std::string& pose = "robot/pose") {
        basecamp::LinkMapBuilder builder(basecamp::PoseSource::parse(pose, "--pose"),
                                         types::TypeLibrary::project_and({}, "--idl"));
        basecamp::RecordingReader(recording_, "FILE").read(builder);
        return builder.build("--pose", recording_);
    }

    std::string recording_, png_;
};

TEST_F(LinkMapTest, ThePathCarriesTheRateOfTheLastStatusAndDropsFromItsCounts) {
    write_recording(recording_, {}, mission());
    const basecamp::LinkMap map = build();
    EXPECT_EQ(map.poses, 76u);
    EXPECT_EQ(map.rate_points, 16u);
    EXPECT_EQ(map.rates_from, "the gateway's status");
    ASSERT_EQ(map.segments.size(), 75u);
    EXPECT_DOUBLE_EQ(map.min_rate_bps, 10'000);
    EXPECT_DOUBLE_EQ(map.max_rate_bps, 70'000);
    // The stretch from t = 2.2 s (x = 22 m) starts after the status of second 2.
    EXPECT_DOUBLE_EQ(map.segments[11].from.x, 22);
    EXPECT_DOUBLE_EQ(*map.segments[11].rate_bps, 58'000);
    EXPECT_EQ(map.drops_from, "the gateway's status counts");
    ASSERT_EQ(map.drops.size(), 1u);
    EXPECT_EQ(map.drops[0].samples, 3u);
    EXPECT_DOUBLE_EQ(map.drops[0].x, 90);
    EXPECT_DOUBLE_EQ(map.drops[0].y, 0);
}

TEST_F(LinkMapTest, ThePictureIsGreenAtTheStartAndRedAtTheFarEnd) {
    write_recording(recording_, {}, mission());
    basecamp::render_link_map(build(), "test", png_, "--out", 600, 400);
    std::unique_ptr<cairo_surface_t, decltype(&cairo_surface_destroy)> image(
        cairo_image_surface_create_from_png(png_.c_str()), &cairo_surface_destroy);
    ASSERT_EQ(cairo_surface_status(image.get()), CAIRO_STATUS_SUCCESS);
    EXPECT_EQ(cairo_image_surface_get_width(image.get()), 600);
    EXPECT_EQ(cairo_image_surface_get_height(image.get()), 400);
    // Count the path's colours: mostly green while x < 50 m, red at x = 100 m and on the way north.
    const unsigned char* data = cairo_image_surface_get_data(image.get());
    const int stride = cairo_image_surface_get_stride(image.get());
    int greenish = 0, reddish = 0;
    for (int y = 0; y < 400; ++y) {
        for (int x = 0; x < 600; ++x) {
            const auto* p = data + y * stride + x * 4;  // B, G, R, x
            if (p[1] > 140 && p[2] < 100 && p[0] < 100)
                ++greenish;
            if (p[2] > 190 && p[1] < 60 && p[0] < 60)
                ++reddish;
        }
    }
    EXPECT_GT(greenish, 200);
    EXPECT_GT(reddish, 200);
}

TEST_F(LinkMapTest, AMissionArchiveGivesEachDroppedSampleItsPlace) {
    std::vector<basecamp::SampleRecord> samples = mission();
    write_recording(recording_, {}, samples);
    // As RecordingReader hands a mission archive's drops: on their own topics, at their source time.
    basecamp::LinkMapBuilder builder(basecamp::PoseSource::parse("robot/pose:x,y", "--pose"),
                                     types::TypeLibrary::project_and({}, "--idl"));
    for (basecamp::SampleRecord& s : samples)
        builder.add(s);
    for (int i : {10, 11, 40}) {  // at x = 20, 22 and 80 m: the first two in one square of the map
        basecamp::SampleRecord dropped =
            sample_of("dropped/expired/telemetry/D", "tgw::idl::PaperMessage", {}, START + i * SECOND / 5);
        builder.add(dropped);
    }
    const basecamp::LinkMap map = builder.build("--pose", "archive");
    EXPECT_EQ(map.drops_from, "the mission archive");
    EXPECT_EQ(map.dropped_samples, 3u);
    ASSERT_EQ(map.drops.size(), 2u);
    EXPECT_DOUBLE_EQ(map.drops[0].x, 21);
    EXPECT_EQ(map.drops[0].samples, 2u);
    EXPECT_DOUBLE_EQ(map.drops[1].x, 80);
}

// The statuses a weak link delays or drops; the gateway's log has the rate all along, and colours the path.
TEST_F(LinkMapTest, TheGatewaysLoggedRatesColourThePathInsteadOfItsStatuses) {
    basecamp::LinkMapBuilder builder(basecamp::PoseSource::parse("robot/pose", "--pose"),
                                     types::TypeLibrary::project_and({}, "--idl"));
    for (basecamp::SampleRecord& s : mission())
        builder.add(s);
    builder.add_logged_rate(START, 64'000);
    builder.add_logged_rate(START + 5 * SECOND, 8'000);
    const basecamp::LinkMap map = builder.build("--pose", "archive");
    EXPECT_EQ(map.rates_from, "the gateway's log");
    EXPECT_EQ(map.rate_points, 2u);
    EXPECT_DOUBLE_EQ(map.min_rate_bps, 8'000);
    EXPECT_DOUBLE_EQ(*map.segments[11].rate_bps, 64'000);  // t = 2.2 s
    EXPECT_DOUBLE_EQ(*map.segments[30].rate_bps, 8'000);   // t = 6 s
}

TEST_F(LinkMapTest, APoseTopicThatIsMissingOrLacksTheFieldsNamesTheFlag) {
    write_recording(recording_, {}, mission());
    EXPECT_EQ(config_error_of([&] { build("robot/elsewhere"); }).rfind("--pose: no sample of 'robot/elsewhere'", 0),
              0u);
    EXPECT_NE(config_error_of([&] { build("robot/pose:x,altitude"); }).find("has no number 'altitude'"),
              std::string::npos);
    EXPECT_EQ(config_error_of([] { basecamp::PoseSource::parse("robot/pose:x", "--pose"); }),
              "--pose: expected TOPIC or TOPIC:FIELD_X,FIELD_Y, not 'robot/pose:x'");
}

}  // namespace
}  // namespace tgw::test
