#pragma once

#include <map>

#include "basecamp/capture/delivery_tally.hpp"

namespace eprosima::fastdds::dds {
class DomainParticipant;
class DataWriter;
}  // namespace eprosima::fastdds::dds

namespace tgw::basecamp {

/// Publishes a DeliveryTally's totals on wire::RECEIVER_REPORT_TOPIC, one instance per gateway (sending
/// participant), reliable keep last 1 so a camp tool's reliable reader matches: each report holds every count, so
/// only the newest matters.
class ReceiverReporter {
  public:
    /// Creates the topic and its writer on `participant`, which owns them. Throws base::ConfigError when DDS
    /// refuses.
    explicit ReceiverReporter(eprosima::fastdds::dds::DomainParticipant* participant);

    /// Writes one report per participant in `totals`; false when a write fails.
    bool publish(const std::map<ParticipantPrefix, DeliveryTotals>& totals);

  private:
    eprosima::fastdds::dds::DataWriter* writer_ = nullptr;
};

}  // namespace tgw::basecamp
