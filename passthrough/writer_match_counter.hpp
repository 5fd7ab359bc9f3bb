// How many readers a DataWriter has matched now, for writers whose owner reports it (the gateway's WAN lanes,
// tm-basecamp relay's local writers).
#pragma once

#include <atomic>
#include <cstdint>

#include <fastdds/dds/publisher/DataWriterListener.hpp>

namespace tgw::passthrough {

class WriterMatchCounter final : public eprosima::fastdds::dds::DataWriterListener {
  public:
    void on_publication_matched(eprosima::fastdds::dds::DataWriter* /*writer*/,
                                const eprosima::fastdds::dds::PublicationMatchedStatus& info) override {
        matched.store(info.current_count);
    }
    std::atomic<std::int32_t> matched{0};
};

}  // namespace tgw::passthrough
