#include "gateway/dds/topic_bridge.hpp"

#include <algorithm>
#include <utility>

#include "gateway/dds/compact_wan.hpp"
#include "gateway/dds/lane_listener.hpp"
#include "gateway/dds/robot_participant.hpp"
#include "gateway/dds/wan_router.hpp"

namespace tgw::dds {

struct TopicBridge::Lane {
    passthrough::OfferedQos offer;
    bool live = false;
    bool declared = false;  ///< made at start-up from a --qos profile, before any publisher
    eprosima::fastdds::dds::DataReader* reader = nullptr;  ///< owned by the robot participant
    std::unique_ptr<LaneListener> listener;
    std::shared_ptr<WanWriter> writer;  ///< a write in progress holds it too
};

TopicBridge::TopicBridge(core::TopicId id, std::string name, std::string wan_name, std::string type_name, bool keyed,
                         passthrough::ResolvedTtl ttl, Ends ends, std::shared_ptr<const types::KeyHasher> key_hasher)
    : id_(id),
      name_(std::move(name)),
      wan_name_(std::move(wan_name)),
      type_name_(std::move(type_name)),
      keyed_(keyed),
      ttl_(ttl),
      ends_(ends),
      key_hasher_(std::move(key_hasher)) {}

TopicBridge::~TopicBridge() = default;

std::optional<std::uint16_t> TopicBridge::lane_for_nts(const passthrough::OfferedQos& offer) const {
    for (std::size_t i = 0; i < lanes_.size(); ++i) {
        if (lanes_[i].live && lanes_[i].offer == offer) {
            return static_cast<std::uint16_t>(i);
        }
    }
    // A lane declared in the --qos file takes any publisher its reader matches: its WAN writer offers what the
    // operator wrote, and its announcement crossed the link at start-up.
    for (std::size_t i = 0; i < lanes_.size(); ++i) {
        if (lanes_[i].live && lanes_[i].declared && lanes_[i].offer.accepts(offer)) {
            return static_cast<std::uint16_t>(i);
        }
    }
    return std::nullopt;
}

bool TopicBridge::admit(const passthrough::DiscoveredPublisher& pub, bool declared) {
    if (const auto lane = lane_for_nts(pub.qos)) {
        // The lane's reader matches this publisher already.
        writers_.assign(pub.writer, *lane);
        return true;
    }
    // A retired lane's index is taken again: lanes do not grow with publishers that come and go.
    const auto retired = std::find_if(lanes_.begin(), lanes_.end(), [](const Lane& lane) { return !lane.live; });
    const auto index = static_cast<std::uint16_t>(retired - lanes_.begin());

    // The WAN writer first, so that nothing the reader takes finds no writer.
    // Lifespan = TTL, so that base-camp readers drop what is stale themselves; but what a latched publisher
    // keeps forever (ROS 2's /tf_static, /robot_description) stays for late joiners past the TTL.
    std::optional<base::Duration> lifespan = ttl_.ttl;
    if (pub.qos.transient_local && !pub.lifespan) {
        lifespan.reset();
    }
    Lane lane;
    lane.offer = pub.qos;
    lane.live = true;
    lane.declared = declared;
    if (ends_.compact != nullptr) {
        // The lane's samples travel in bundles; the catalog tells the base camp what to republish them as.
        ends_.compact->announce(CatalogLane{id_, wan_name_, type_name_, keyed_, ttl_.ttl, index, pub.qos, lifespan});
    } else {
        lane.writer = ends_.wan.create_writer(name_, wan_name_, type_name_, keyed_, lifespan, pub.qos, pub.type_object);
        if (lane.writer == nullptr) {
            return false;
        }
    }
    lane.listener =
        std::make_unique<LaneListener>(id_, name_, index, keyed_, writers_, ends_.loop, ends_.clock, key_hasher_);
    lane.reader = ends_.robot.create_reader(name_, type_name_, keyed_, pub.qos, lane.listener.get());
    if (lane.reader == nullptr) {
        return false;
    }
    // After the reader exists: until now the writer's samples came through the lane that had them, if any.
    if (pub.writer != eprosima::fastrtps::rtps::GUID_t::unknown()) {
        writers_.assign(pub.writer, index);
    }
    std::lock_guard<std::mutex> lock(mutex_);
    if (index == lanes_.size()) {
        lanes_.push_back(std::move(lane));
    } else {
        lanes_[index] = std::move(lane);
    }
    if (std::count_if(lanes_.begin(), lanes_.end(), [](const Lane& l) { return l.live; }) > 1) {
        writers_.several_lanes();
    }
    return true;
}

std::optional<std::uint16_t> TopicBridge::release(const eprosima::fastrtps::rtps::GUID_t& writer) {
    const std::optional<std::uint16_t> lane = writers_.release(writer);
    if (!lane || writers_.writers_on(*lane) > 0 || lanes_[*lane].declared) {
        return std::nullopt;
    }
    return lane;
}

void TopicBridge::retire(std::uint16_t index) {
    if (index >= lanes_.size() || !lanes_[index].live || writers_.writers_on(index) > 0) {
        return;
    }
    Lane& lane = lanes_[index];
    ends_.robot.delete_reader(lane.reader);  // no callback into the listener after this
    std::unique_ptr<LaneListener> listener;
    std::shared_ptr<WanWriter> writer;
    {
        std::lock_guard<std::mutex> lock(mutex_);
        lane.reader = nullptr;
        listener = std::move(lane.listener);
        writer = std::move(lane.writer);
        lane.live = false;
    }
    // The writer goes here, or after the write that holds it now.
}

void TopicBridge::close_readers() {
    for (Lane& lane : lanes_) {
        if (lane.reader != nullptr) {
            ends_.robot.delete_reader(lane.reader);
            std::lock_guard<std::mutex> lock(mutex_);
            lane.reader = nullptr;
        }
    }
}

bool TopicBridge::idle() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return std::none_of(lanes_.begin(), lanes_.end(), [](const Lane& lane) { return lane.live; });
}

WriteResult TopicBridge::write(core::Sample& sample, AfterWrite after) const {
    std::shared_ptr<WanWriter> writer;
    {
        std::lock_guard<std::mutex> lock(mutex_);
        if (sample.route < lanes_.size()) {
            writer = lanes_[sample.route].writer;
        }
    }
    return writer ? writer->write(sample, after) : WriteResult::unknown_topic;
}

std::int32_t TopicBridge::matched_writers() const {
    std::lock_guard<std::mutex> lock(mutex_);
    std::int32_t matched = 0;
    for (const Lane& lane : lanes_) {
        matched += lane.listener ? lane.listener->matched_writers() : 0;
    }
    return matched;
}

std::int32_t TopicBridge::matched_readers() const {
    if (ends_.compact != nullptr) {
        return ends_.compact->matched_readers();
    }
    std::lock_guard<std::mutex> lock(mutex_);
    std::int32_t matched = 0;
    for (const Lane& lane : lanes_) {
        matched += lane.writer ? lane.writer->matched_readers() : 0;
    }
    return matched;
}

bool TopicBridge::reaches_anyone() const {
    if (ends_.compact != nullptr) {
        return ends_.compact->matched_readers() > 0;
    }
    std::lock_guard<std::mutex> lock(mutex_);
    for (const Lane& lane : lanes_) {
        if (lane.writer && (lane.writer->matched_readers() > 0 || (lane.live && lane.offer.transient_local))) {
            return true;
        }
    }
    return false;
}

std::optional<base::Duration> TopicBridge::writer_lifespan(std::uint16_t index) const {
    std::lock_guard<std::mutex> lock(mutex_);
    if (index >= lanes_.size() || !lanes_[index].writer) {
        return std::nullopt;
    }
    return lanes_[index].writer->lifespan();
}

BridgedTopic TopicBridge::describe() const {
    BridgedTopic out;
    out.id = id_;
    out.name = name_;
    out.type_name = type_name_;
    out.keyed = keyed_;
    out.ttl = ttl_;
    std::lock_guard<std::mutex> lock(mutex_);
    for (const Lane& lane : lanes_) {
        out.lanes.push_back(lane.offer);
        out.live.push_back(lane.live);
    }
    return out;
}

}  // namespace tgw::dds
