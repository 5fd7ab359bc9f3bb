#pragma once

#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <deque>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <ostream>
#include <string>
#include <vector>

#include "base/peer_transport.hpp"
#include "base/security_files.hpp"
#include "base/time.hpp"
#include "basecamp/capture/discovery_queue.hpp"
#include "basecamp/decode/sample_printer.hpp"
#include "passthrough/discovery.hpp"
#include "passthrough/lane_assignment.hpp"
#include "passthrough/partition_groups.hpp"
#include "types/type_library.hpp"

namespace eprosima::fastdds::dds {
class DomainParticipant;
class Subscriber;
}  // namespace eprosima::fastdds::dds

namespace tgw::basecamp {

/// Subscribes to one topic on a domain, whatever its type (tgw::passthrough::PassthroughType), and prints each sample
/// as it arrives (SamplePrinter): decoded when `types` has the IDL of the type its publishers announce, or else the
/// first publisher announced an XTypes TypeObject of it (type_object_idl()); as size and hex otherwise. Each QoS its
/// publishers offer gets a reader asking for exactly that (one lane, as the relay has them), and each sample is printed
/// once, from its writer's lane.
class Echo {
  public:
    /// Creates the participant, with DDS Security when `security` is given. `out` must outlive the Echo. Throws
    /// base::ConfigError naming --domain, --peer or --interface when DDS refuses it.
    Echo(int domain, const base::PeerTransport& transport, std::string topic, types::TypeLibrary types,
         SamplePrinter::Format format, std::ostream& out,
         const std::optional<base::SecurityFiles>& security = std::nullopt);
    ~Echo();
    Echo(const Echo&) = delete;
    Echo& operator=(const Echo&) = delete;

    /// Subscribes as publishers of the topic appear and prints their samples, in this thread, until `count`
    /// were printed (0: no limit), `duration` has passed or `stop` turns true. The number of samples printed.
    std::uint64_t run(std::uint64_t count, base::Duration duration, const std::atomic<bool>& stop);

    /// The type name the topic's publishers announce; empty until one was discovered.
    std::string type_name() const;

  private:
    class Lane;

    void subscribe(const passthrough::DiscoveredPublisher& publisher);
    /// Adds the IDL of the type the first publisher announced in its TypeObject, when `types_` lacks it; what
    /// echo tells the operator about how samples will print.
    std::string learn_announced_type(const passthrough::DiscoveredPublisher& publisher);
    /// For the lanes' listeners (Fast DDS's threads): queues a sample for run().
    void push(ReceivedSample&& sample);
    /// What arrived since the last call; waits up to `timeout` for the first.
    std::vector<ReceivedSample> take(std::chrono::milliseconds timeout);

    const std::string topic_;
    types::TypeLibrary types_;
    const SamplePrinter::Format format_;
    std::ostream& out_;
    std::string type_name_;
    bool keyed_ = false;
    std::optional<SamplePrinter> printer_;

    DiscoveryQueue discovered_;  ///< before discovery_, whose callback feeds it
    std::unique_ptr<passthrough::Discovery> discovery_;
    eprosima::fastdds::dds::DomainParticipant* participant_ = nullptr;
    passthrough::PartitionGroups<eprosima::fastdds::dds::Subscriber> subscribers_;
    passthrough::LaneAssignment writers_;
    std::vector<std::unique_ptr<Lane>> lanes_;

    mutable std::mutex mutex_;
    std::condition_variable arrived_;
    std::deque<ReceivedSample> queued_;
};

}  // namespace tgw::basecamp
