// The relay's DDS endpoints of backfill on the WAN domain: the reader of the gateways' backfilled samples and the
// writer of the camp's acknowledgements.
#pragma once

#include <chrono>
#include <memory>

#include <fastdds/dds/subscriber/DataReaderListener.hpp>

#include "basecamp/capture/backfill_archive.hpp"

namespace eprosima::fastdds::dds {
class DataReader;
class DataWriter;
class DomainParticipant;
}  // namespace eprosima::fastdds::dds

namespace tgw::basecamp {

/// Reads wire::BACKFILL_TOPIC into a BackfillArchive (best effort, as the gateways write it: the acknowledgements
/// make it reliable) and writes the archive's acknowledgements on wire::BACKFILL_ACK_TOPIC (reliable, a few kept
/// per log). Made with the relay's WAN participant, which owns the entities; a gateway sends backfill only while
/// such a reader matches its writer.
class BackfillEndpoints final : public eprosima::fastdds::dds::DataReaderListener {
  public:
    /// Throws base::ConfigError when DDS refuses an entity. `archive` must outlive the endpoints.
    BackfillEndpoints(eprosima::fastdds::dds::DomainParticipant* wan, BackfillArchive& archive);
    /// The endpoints, or nullptr after saying why on stderr: a camp whose DDS Security permissions predate backfill
    /// (no grant to publish tgw/backfill_ack) records on without it, and no gateway sends it backfill.
    static std::unique_ptr<BackfillEndpoints> make_or_say_why(eprosima::fastdds::dds::DomainParticipant* wan,
                                                              BackfillArchive& archive);
    ~BackfillEndpoints() override;

    void on_data_available(eprosima::fastdds::dds::DataReader* reader) override;

    /// Writes the acknowledgements due (BackfillArchive::take_acks) once ACK_PERIOD has passed since the last
    /// time; the owner calls it from its loop as often as it likes.
    void publish_acks_when_due();
    /// A row's acknowledgement comes long before its resend (5 s), and costs the robot's uplink little.
    static constexpr std::chrono::milliseconds ACK_PERIOD{500};

  private:
    BackfillArchive& archive_;
    eprosima::fastdds::dds::DataReader* reader_ = nullptr;
    eprosima::fastdds::dds::DataWriter* writer_ = nullptr;
    std::chrono::steady_clock::time_point next_acks_{};
};

}  // namespace tgw::basecamp
