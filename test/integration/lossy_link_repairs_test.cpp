// Repairs over a link that loses a datagram, in standard WAN mode: the base camp's reader is reliable (its vendor's
// usual choice), the gateway's WAN participant sends through Fast DDS's test_UDPv4Transport, which loses the
// datagrams a test chooses as a radio would. A repair waits while it would cost a more urgent sample its
// deadline, and a repair of a sample past its deadline never reaches the link. Real participants on loopback, the
// gateway's own budget as the link.
#include <gtest/gtest.h>

#include <fastdds/rtps/transport/test_UDPv4TransportDescriptor.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cstdint>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "PaperWorkloadPubSubTypes.h"
#include "test/integration/gateway_fixture.hpp"

namespace tgw::test {
namespace {

using namespace std::chrono_literals;
using eprosima::fastrtps::rtps::CDRMessage_t;
using Clock = std::chrono::steady_clock;

/// The WAN link: sees every application DATA and HEARTBEAT the gateway sends, and loses those it is told to.
/// A sample is known by its payload: every byte of it is one marker value.
class LossyLink {
  public:
    LossyLink() : descriptor_(std::make_shared<eprosima::fastdds::rtps::test_UDPv4TransportDescriptor>()) {
        descriptor_->drop_data_messages_filter_ = [this](CDRMessage_t& msg) { return on_data(msg); };
        descriptor_->drop_heartbeat_messages_filter_ = [this](CDRMessage_t& msg) { return on_heartbeat(msg); };
    }

    std::shared_ptr<eprosima::fastdds::rtps::TransportDescriptorInterface> transport() const { return descriptor_; }

    /// Loses the next DATA of a sample marked `marker`, and every HEARTBEAT of its writer until `until`: a reader
    /// learns of the loss only then, from the writer's periodic HEARTBEAT.
    void lose_next(std::uint8_t marker, Clock::time_point until) {
        std::lock_guard<std::mutex> lock(mutex_);
        lose_marker_ = marker;
        heartbeats_lost_until_ = until;
    }

    /// How many DATA of a sample marked `marker` the gateway put on the link, the lost included.
    std::size_t sent(std::uint8_t marker) const {
        std::lock_guard<std::mutex> lock(mutex_);
        std::size_t n = 0;
        for (std::uint8_t m : sent_) {
            n += m == marker ? 1 : 0;
        }
        return n;
    }
    std::size_t lost() const {
        std::lock_guard<std::mutex> lock(mutex_);
        return lost_;
    }

  private:
    using EntityId = std::array<std::uint8_t, 4>;

    /// The submessage whose body starts at msg.pos: its body's bytes (the transport has read its header).
    static std::pair<const std::uint8_t*, std::size_t> body(const CDRMessage_t& msg) {
        const bool little = (msg.buffer[msg.pos - 3] & 0x01) != 0;
        const std::uint8_t lo = msg.buffer[msg.pos - (little ? 2 : 1)];
        const std::uint8_t hi = msg.buffer[msg.pos - (little ? 1 : 2)];
        std::size_t length = static_cast<std::size_t>(hi) << 8 | lo;
        if (length == 0 || msg.pos + length > msg.length) {
            length = msg.length - msg.pos;  // the message's last submessage
        }
        return {msg.buffer + msg.pos, length};
    }

    /// The marker of the sample a DATA's body carries: a run of 32 equal bytes, or none.
    static std::optional<std::uint8_t> marker_of(const std::uint8_t* bytes, std::size_t size) {
        constexpr std::size_t RUN = 32;
        std::size_t run = 1;
        for (std::size_t i = 1; i < size; ++i) {
            run = bytes[i] == bytes[i - 1] ? run + 1 : 1;
            if (run == RUN && bytes[i] != 0) {
                return bytes[i];
            }
        }
        return std::nullopt;
    }

    bool on_data(const CDRMessage_t& msg) {
        const auto [bytes, size] = body(msg);
        const std::optional<std::uint8_t> marker = marker_of(bytes, size);
        if (!marker || size < 12) {
            return false;
        }
        std::lock_guard<std::mutex> lock(mutex_);
        sent_.push_back(*marker);
        if (lose_marker_ != marker) {
            return false;
        }
        lose_marker_.reset();
        EntityId writer{};
        std::copy(bytes + 8, bytes + 12, writer.begin());  // extraFlags, octetsToInlineQos, readerId, writerId
        losing_heartbeats_of_.push_back(writer);
        ++lost_;
        return true;
    }

    bool on_heartbeat(const CDRMessage_t& msg) {
        const auto [bytes, size] = body(msg);
        if (size < 8) {
            return false;
        }
        EntityId writer{};
        std::copy(bytes + 4, bytes + 8, writer.begin());  // readerId, writerId
        std::lock_guard<std::mutex> lock(mutex_);
        return Clock::now() < heartbeats_lost_until_ &&
               std::find(losing_heartbeats_of_.begin(), losing_heartbeats_of_.end(), writer) !=
                   losing_heartbeats_of_.end();
    }

    std::shared_ptr<eprosima::fastdds::rtps::test_UDPv4TransportDescriptor> descriptor_;
    mutable std::mutex mutex_;
    std::vector<std::uint8_t> sent_;
    std::optional<std::uint8_t> lose_marker_;
    std::vector<EntityId> losing_heartbeats_of_;
    Clock::time_point heartbeats_lost_until_;
    std::size_t lost_ = 0;
};

constexpr std::uint8_t HAZARD = 0x48;
constexpr std::uint8_t PICTURE = 0x50;

class LossyLinkRepairTest : public GatewayIntegrationTest {
  protected:
    void start(double rate_bps) {
        GatewayConfig c = config();
        c.scheduler.initial_rate_bps = rate_bps;
        c.wan_datagram_transport = link_.transport();
        start_gateway(c);
    }

    /// A robot writer of `topic` with Lifespan `ttl` and a base camp reader with its vendor's reliable defaults.
    fdds::DataWriter* bridge_reliably(const std::string& topic, base::Duration ttl,
                                      CollectingReader<idl::PaperMessage>& camp) {
        auto& writer_matches = listener<MatchCounter>();
        auto* writer = robot_->make_writer(topic, fdds::TypeSupport(new idl::PaperMessagePubSubType()),
                                           robot_writer_qos(*robot_, ttl), &writer_matches);
        fdds::DataReaderQos reliable = basecamp_->default_reader_qos();
        reliable.reliability().kind = fdds::RELIABLE_RELIABILITY_QOS;
        auto* reader =
            basecamp_->make_reader(topic, fdds::TypeSupport(new idl::PaperMessagePubSubType()), reliable, &camp);
        if (writer == nullptr || reader == nullptr) {
            ADD_FAILURE() << "cannot create the writer or the reader of " << topic;
            return nullptr;
        }
        wait_for_bridge(topic, writer_matches, camp.matched);
        return HasFatalFailure() ? nullptr : writer;
    }

    static bool write(fdds::DataWriter* writer, std::uint8_t marker, std::size_t bytes) {
        idl::PaperMessage msg;
        msg.data(std::vector<std::uint8_t>(bytes, marker));
        return writer->write(&msg);
    }

    LossyLink link_;
};

TEST_F(LossyLinkRepairTest, ARepairThatCannotArriveBeforeItsSamplesDeadlineIsNeverSent) {
    start(1e6);
    auto& pictures = listener<CollectingReader<idl::PaperMessage>>();
    auto* picture = bridge_reliably(topic_prefix_ + "picture", 4s, pictures);
    ASSERT_NE(picture, nullptr);

    // The reader hears of the loss from the writer's periodic HEARTBEAT, about 3 s after the write: 1 s before the
    // sample's deadline, on a link where its repair takes 9 s.
    link_.lose_next(PICTURE, Clock::now() + 2s);
    ASSERT_TRUE(write(picture, PICTURE, 1'000));
    ASSERT_TRUE(wait_until([&] { return link_.lost() == 1; }, 2s));
    gateway_->set_rate(1'000);
    ASSERT_TRUE(wait_until([&] { return gateway_->repair_counters().received >= 1; }, 6s))
        << "the reader never asked for the lost sample again";
    ASSERT_TRUE(wait_until([&] { return gateway_->repair_counters().late >= 1; }, 2s))
        << "the repair was not found late";
    gateway_->set_rate(1e6);  // and once the link is fast again, nothing of it goes either
    std::this_thread::sleep_for(2s);

    EXPECT_EQ(link_.sent(PICTURE), 1u) << "the lost DATA only: no repair of it reached the link";
    EXPECT_EQ(pictures.count(), 0u);
    EXPECT_EQ(gateway_->repair_counters().sent, 0u);
    expect_balanced();
}

TEST_F(LossyLinkRepairTest, ARepairThatWouldCostAMoreUrgentSampleItsDeadlineWaitsForAFasterLink) {
    start(1e6);
    auto& hazards = listener<CollectingReader<idl::PaperMessage>>();
    auto* hazard = bridge_reliably(topic_prefix_ + "hazard", 1s, hazards);
    auto& pictures = listener<CollectingReader<idl::PaperMessage>>();
    auto* picture = bridge_reliably(topic_prefix_ + "picture", 20s, pictures);
    ASSERT_NE(hazard, nullptr);
    ASSERT_NE(picture, nullptr);

    std::size_t hazards_written = 0;
    auto next_hazard = Clock::now();
    // A hazard every 0.5 s: its topic is active, and nothing may hold the link for longer than its room.
    const auto hazards_for = [&](base::Duration span) {
        const auto end = Clock::now() + span;
        while (Clock::now() < end) {
            if (Clock::now() >= next_hazard) {
                ASSERT_TRUE(write(hazard, HAZARD, 40));
                ++hazards_written;
                next_hazard += 500ms;
            }
            std::this_thread::sleep_for(10ms);
        }
    };
    hazards_for(1s);

    link_.lose_next(PICTURE, Clock::now() + 1s);
    ASSERT_TRUE(write(picture, PICTURE, 1'100));
    ASSERT_TRUE(wait_until([&] { return link_.lost() == 1; }, 2s));
    // At 8,000 bit/s the picture's repair holds the link for about 1.2 s; a hazard has under 1 s.
    gateway_->set_rate(8'000);
    for (int i = 0; i < 16 && gateway_->repair_counters().received == 0; ++i) {
        hazards_for(500ms);
    }
    ASSERT_GE(gateway_->repair_counters().received, 1u) << "the reader never asked for the lost picture again";
    hazards_for(2s);

    EXPECT_EQ(gateway_->repair_counters().sent, 0u) << "the repair went while hazards were due";
    EXPECT_EQ(link_.sent(PICTURE), 1u);
    EXPECT_EQ(pictures.count(), 0u);
    ASSERT_TRUE(wait_until([&] { return hazards.count() == hazards_written; }, 2s))
        << hazards.count() << " of " << hazards_written << " hazards arrived";
    for (const auto& h : hazards.received()) {
        const auto took = h.info.reception_timestamp.to_ns() - h.info.source_timestamp.to_ns();
        EXPECT_LT(took, std::chrono::nanoseconds(1s).count()) << "a hazard arrived past its deadline";
    }

    gateway_->set_rate(1e6);
    ASSERT_TRUE(wait_until([&] { return pictures.count() == 1; }, 5s)) << "the repair never went";
    EXPECT_EQ(pictures.received()[0].data.data().size(), 1'100u);
    EXPECT_GE(gateway_->repair_counters().sent, 1u);
    EXPECT_EQ(link_.sent(PICTURE), 2u) << "the lost DATA, then its repair";
    expect_balanced();
}

}  // namespace
}  // namespace tgw::test
