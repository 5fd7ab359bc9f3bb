// One subscriber's samples handed to several consumers: record --out and --mcap at once.
#pragma once

#include <vector>

#include "basecamp/sample/sample_consumer.hpp"

namespace tgw::basecamp {

class ConsumerFanOut final : public SampleConsumer {
  public:
    /// Each consumer must outlive this.
    explicit ConsumerFanOut(std::vector<SampleConsumer*> consumers) : consumers_(std::move(consumers)) {}

    void add_topic(TopicRecord topic) override {
        for (SampleConsumer* consumer : consumers_)
            consumer->add_topic(topic);
    }

    void add(SampleRecord sample) override {
        for (std::size_t i = 0; i + 1 < consumers_.size(); ++i)
            consumers_[i]->add(sample);
        if (!consumers_.empty())
            consumers_.back()->add(std::move(sample));
    }

    void add_channel(const ChannelRecord& channel) override {
        for (SampleConsumer* consumer : consumers_)
            consumer->add_channel(channel);
    }

  private:
    std::vector<SampleConsumer*> consumers_;
};

}  // namespace tgw::basecamp
