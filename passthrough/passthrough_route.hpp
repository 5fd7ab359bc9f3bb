// One topic passed through from a reader on one participant to a writer of the same topic and type on another:
// tm-basecamp relay's lanes (the WAN onto the camp's domain) and the uplink's routes (commands back to the robot).
#pragma once

#include <cstdint>
#include <optional>

#include <fastdds/rtps/common/Time_t.h>
#include <fastrtps/types/TypesBase.h>
#include <fastdds/dds/publisher/qos/DataWriterQos.hpp>
#include <fastdds/dds/subscriber/DataReaderListener.hpp>
#include <fastdds/dds/subscriber/SampleInfo.hpp>
#include <fastdds/dds/subscriber/qos/DataReaderQos.hpp>

#include "passthrough/passthrough_type.hpp"
#include "passthrough/writer_match_counter.hpp"

namespace eprosima::fastdds::dds {
class DataWriter;
class Publisher;
class Subscriber;
class Topic;
}  // namespace eprosima::fastdds::dds

namespace tgw::passthrough {

/// The reader's listener takes every sample and writes it on the writer as it came (pass_on): its bytes, its
/// instance, its dispose or unregister, stamped as the subclass says. An unkeyed topic's sample without data is
/// skipped: its one instance has nothing to pass on. The subclass decides each sample (`admit`) and hears how its
/// write went (`written`), in the thread that takes it.
///
/// The writer is made first, so that nothing the reader takes finds none; the reader is deleted first (its listener
/// detached), so that no callback finds the writer gone.
class PassthroughRoute : public eprosima::fastdds::dds::DataReaderListener {
  public:
    explicit PassthroughRoute(bool keyed) : keyed_(keyed) {}
    /// The reader, then the writer.
    ~PassthroughRoute() override;
    PassthroughRoute(const PassthroughRoute&) = delete;
    PassthroughRoute& operator=(const PassthroughRoute&) = delete;

    /// Creates the writer of `topic` on `publisher`, counting the readers it matches. False when Fast DDS refuses.
    bool open_writer(eprosima::fastdds::dds::Publisher& publisher, eprosima::fastdds::dds::Topic* topic,
                     const eprosima::fastdds::dds::DataWriterQos& qos);
    /// Creates the reader of `topic` on `subscriber`, this its listener; after open_writer(). False when Fast DDS
    /// refuses, or when there is no writer.
    bool attach_reader(eprosima::fastdds::dds::Subscriber& subscriber, eprosima::fastdds::dds::Topic* topic,
                       const eprosima::fastdds::dds::DataReaderQos& qos);
    /// Deletes the reader, whose participant is to go; the writer stays, for a reader attached again later.
    void detach_reader();
    bool has_reader() const { return reader_ != nullptr; }

    /// The readers the writer has matched now.
    std::int32_t readers_matched() const { return writer_matches_.matched.load(); }

    void on_data_available(eprosima::fastdds::dds::DataReader* reader) final;

  protected:
    /// The stamp to write a taken sample with, or nullopt to pass it over. `info.valid_data` is false for a keyed
    /// instance's dispose or unregister.
    virtual std::optional<eprosima::fastrtps::Time_t> admit(const PassthroughData& data,
                                                            const eprosima::fastdds::dds::SampleInfo& info) = 0;
    /// How the write of an admitted sample went; `reader_matched`: whether the writer had matched a reader just
    /// before it (one that matches during the write may or may not have it).
    virtual void written(eprosima::fastrtps::types::ReturnCode_t rc, bool reader_matched) = 0;

  private:
    const bool keyed_;
    eprosima::fastdds::dds::DataReader* reader_ = nullptr;
    eprosima::fastdds::dds::DataWriter* writer_ = nullptr;
    WriterMatchCounter writer_matches_;
};

}  // namespace tgw::passthrough
