#include "basecamp/recording/mcap_recording.hpp"

#include <utility>

namespace tgw::basecamp {

namespace {

constexpr char SCHEMA_ENCODING[] = "omgidl";
constexpr char MESSAGE_ENCODING[] = "cdr";

}  // namespace

McapRecording::McapRecording(const std::string& path, const std::string& flag, types::TypeLibrary types,
                             McapCompression compression, std::size_t chunk_bytes)
    : types_(std::move(types)), writer_(path, flag, compression, chunk_bytes) {}

std::uint16_t McapRecording::schema_nts(const TopicRecord& topic) {
    const auto known = schemas_.find(topic.type_name);
    if (known != schemas_.end())
        return known->second;
    std::string idl = types_.idl_text(topic.type_name);
    if (idl.empty())
        idl = topic.announced_idl;
    const std::uint16_t id = idl.empty() ? 0 : writer_.add_schema(topic.type_name, SCHEMA_ENCODING, idl);
    schemas_.emplace(topic.type_name, id);
    return id;
}

std::uint16_t McapRecording::channel_nts(const TopicRecord& topic) {
    const auto known = channels_.find(topic.topic);
    if (known != channels_.end())
        return known->second;
    const std::uint16_t schema = schema_nts(topic);
    if (schema == 0)
        ++without_schema_;
    std::map<std::string, std::string> metadata{{"dds_type_name", topic.type_name},
                                                {"keyed", topic.keyed ? "true" : "false"},
                                                {"reliable", topic.reliable ? "true" : "false"}};
    if (topic.lifespan_ns)
        metadata.emplace("lifespan_ns", std::to_string(*topic.lifespan_ns));
    const std::uint16_t id = writer_.add_channel(schema, topic.topic, MESSAGE_ENCODING, metadata);
    channels_.emplace(topic.topic, id);
    return id;
}

void McapRecording::add_topic(TopicRecord topic) {
    std::lock_guard<std::mutex> lock(mutex_);
    channel_nts(topic);
}

void McapRecording::add(SampleRecord sample) {
    std::lock_guard<std::mutex> lock(mutex_);
    const auto known = channels_.find(sample.topic);
    std::uint16_t channel = 0;
    if (known != channels_.end()) {
        channel = known->second;
    } else {
        TopicRecord topic;
        topic.topic = sample.topic;
        topic.type_name = sample.type_name;
        topic.lifespan_ns = sample.lifespan_ns;
        channel = channel_nts(topic);
    }
    // A backfilled sample is logged at its source time: a player shows it when the robot produced it, not hours
    // later when it reached the camp.
    const std::int64_t log_ns = sample.backfill ? sample.source_ns : sample.receive_ns;
    writer_.write_message(channel, static_cast<std::uint64_t>(log_ns), static_cast<std::uint64_t>(sample.source_ns),
                          sample.payload.data(), sample.payload.size());
}

bool McapRecording::close() {
    std::lock_guard<std::mutex> lock(mutex_);
    return writer_.close();
}

std::uint64_t McapRecording::messages() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return writer_.messages();
}

std::uint64_t McapRecording::channels_without_schema() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return without_schema_;
}

}  // namespace tgw::basecamp
