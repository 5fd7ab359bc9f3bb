#pragma once

#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <deque>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include "base/peer_transport.hpp"
#include "base/security_files.hpp"
#include "base/time.hpp"
#include "basecamp/capture/delivery_tally.hpp"
#include "basecamp/capture/discovery_queue.hpp"
#include "basecamp/sample/sample_consumer.hpp"
#include "passthrough/discovery.hpp"

namespace eprosima::fastdds::dds {
class DomainParticipant;
class Subscriber;
class DataReader;
}  // namespace eprosima::fastdds::dds

namespace tgw::basecamp {

class BackfillArchive;
class BackfillEndpoints;
class ReceiverReporter;

/// Subscribes to every topic that appears on a domain, whatever its type (tgw::passthrough::PassthroughType), and
/// hands each received sample to a SampleConsumer (a recording, live statistics). Every `report_period` it tells each
/// sending gateway what arrived and what was lost on the way (ReceiverReporter, DeliveryTally).
class Recorder {
  public:
    /// Creates the participant, with DDS Security when `security` is given. `report_period` zero: no receiver
    /// reports. Throws base::ConfigError when DDS refuses it.
    Recorder(int domain, const base::PeerTransport& transport, SampleConsumer& store,
             base::Duration report_period = std::chrono::seconds(1),
             const std::optional<base::SecurityFiles>& security = std::nullopt);
    ~Recorder();
    Recorder(const Recorder&) = delete;
    Recorder& operator=(const Recorder&) = delete;

    /// Backfill (docs/design/backfill.md): the gateways' backfilled samples go into `archive` and its
    /// acknowledgements back to them (before run()). Without it, backfill is not read, and no gateway sends it.
    /// Throws base::ConfigError when DDS refuses an entity. `archive` must outlive the recorder.
    void archive_backfill(BackfillArchive& archive);

    /// Subscribes to these topics only (before run()); by default to every topic.
    void only(std::vector<std::string> topics) { only_ = std::move(topics); }

    /// Creates readers for topics as they are discovered, until `duration` has passed or `stop` turns true.
    void run(base::Duration duration, const std::atomic<bool>& stop);

    /// Takes no more samples: the participant goes, and with it every reader. What was received stays counted.
    /// Call before the consumers are closed, or a sample that arrives meanwhile reaches some of them only.
    void stop();

    /// Samples received so far, per topic.
    std::map<std::string, std::uint64_t> received() const;
    /// Writers the reader of `topic` has matched now; 0 before the topic has a reader. A writer's samples reach
    /// the recording from its match on: with DDS Security, once the two have exchanged their keys.
    std::int32_t matched_writers(const std::string& topic) const;
    /// Received and lost samples so far, per sending participant.
    std::map<ParticipantPrefix, DeliveryTotals> delivery() const { return tally_.totals(); }

  private:
    class TopicReader;

    void subscribe(const passthrough::DiscoveredPublisher& publisher);

    SampleConsumer& store_;
    DeliveryTally tally_;
    base::Duration report_period_;
    /// Kept across run() calls, so that a caller may run in slices.
    base::SteadyTime next_report_ = base::SteadyClock::now() + report_period_;
    DiscoveryQueue discovered_;  ///< before discovery_, whose callback feeds it
    std::unique_ptr<passthrough::Discovery> discovery_;
    eprosima::fastdds::dds::DomainParticipant* participant_ = nullptr;
    eprosima::fastdds::dds::Subscriber* subscriber_ = nullptr;
    mutable std::mutex readers_mutex_;  ///< readers_ is filled by run() and read from other threads
    std::map<std::string, std::unique_ptr<TopicReader>> readers_;
    std::vector<std::string> only_;
    std::unique_ptr<BackfillEndpoints> backfill_;  ///< with an archive; before the participant goes
    std::unique_ptr<ReceiverReporter> reporter_;
};

}  // namespace tgw::basecamp
