// The gateway's reader of the base camp's backfill acknowledgements (wire::BACKFILL_ACK_TOPIC).
#pragma once

#include <mutex>

#include <fastdds/dds/subscriber/DataReaderListener.hpp>

namespace tgw::dds {

class BackfillSender;

/// Hands every acknowledgement to the sender, in Fast DDS's thread; the sender keeps only those of its own log.
class BackfillAckReader final : public eprosima::fastdds::dds::DataReaderListener {
  public:
    explicit BackfillAckReader(BackfillSender& sender) : sender_(&sender) {}

    void on_data_available(eprosima::fastdds::dds::DataReader* reader) override;

    /// Hands nothing more: once it returns, the sender may go while the reader still exists.
    void close();

  private:
    std::mutex mutex_;
    BackfillSender* sender_;  // under mutex_; null once closed
};

}  // namespace tgw::dds
