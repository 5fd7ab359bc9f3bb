// Where a base-camp subscriber (Recorder) hands what it takes off a domain: a recording (SampleStore), live
// statistics (TopicStats), ...
#pragma once

#include "basecamp/sample/sample_record.hpp"

namespace tgw::basecamp {

/// Called from DDS threads, several at once: implementations are thread-safe and return quickly.
class SampleConsumer {
  public:
    virtual ~SampleConsumer() = default;
    /// A topic whose writer was discovered, before its first sample.
    virtual void add_topic(TopicRecord topic) = 0;
    virtual void add(SampleRecord sample) = 0;
    /// A round of the fleet's grants, where the relay shares a channel; most consumers have no use for it.
    virtual void add_channel(const ChannelRecord& /*channel*/) {}
};

}  // namespace tgw::basecamp
