#pragma once

#include <atomic>
#include <cstdint>
#include <ostream>
#include <string>
#include <vector>

#include "base/peer_transport.hpp"
#include "core/paper_workload.hpp"

namespace eprosima::fastdds::dds {
class DomainParticipant;
class Publisher;
class DataWriter;
}  // namespace eprosima::fastdds::dds

namespace tgw::robot_sim {

/// What one stream published.
struct StreamReport {
    core::MessageStream stream;
    std::uint64_t written = 0;
    std::uint64_t failed = 0;          ///< write() returned an error
    std::uint64_t late = 0;            ///< published more than one period after its due time
    double max_lag_ms = 0.0;           ///< worst delay of a publication behind its due time
    std::size_t serialized_bytes = 0;  ///< payload size on the wire, CDR with encapsulation
};

/// How long the writers keep what they wrote for readers that join later (DDS Durability).
enum class WriterDurability {
    volatile_kind,    ///< for the readers matched when it is written only
    transient_local,  ///< also for a late joiner, within the history and the Lifespan: Fast DDS's default
};

/// Publishes a workload as tgw::idl::PaperMessage, one topic and writer per stream, Lifespan = the stream's
/// TTL, source timestamp = generated_ns = the wall clock at publication.
class PaperPublisher {
  public:
    /// Creates the participant and writers. Throws base::ConfigError when DDS refuses them.
    PaperPublisher(int domain, const std::vector<core::MessageStream>& streams, const base::PeerTransport& transport,
                   WriterDurability durability = WriterDurability::volatile_kind);
    ~PaperPublisher();
    PaperPublisher(const PaperPublisher&) = delete;
    PaperPublisher& operator=(const PaperPublisher&) = delete;

    /// Publishes every stream at its rate for `duration` (steady clock, sleep_until), or until `stop` turns
    /// true. Returns one report per stream.
    std::vector<StreamReport> run(base::Duration duration, const std::atomic<bool>& stop);

    /// Waits at most `max_wait` until every writer has matched a reader; returns how many have not. Without it
    /// an experiment loses its first second or two to discovery, samples that no gateway could have seen.
    std::size_t wait_for_readers(base::Duration max_wait);

    /// Waits at most `max_wait` for matched readers to acknowledge what was written.
    void linger(base::Duration max_wait);

  private:
    std::vector<core::MessageStream> streams_;
    eprosima::fastdds::dds::DomainParticipant* participant_ = nullptr;
    eprosima::fastdds::dds::Publisher* publisher_ = nullptr;
    std::vector<eprosima::fastdds::dds::DataWriter*> writers_;
};

/// Prints the reports as a table, one line per stream plus a total.
void print_reports(std::ostream& out, const std::vector<StreamReport>& reports, double seconds);

}  // namespace tgw::robot_sim
