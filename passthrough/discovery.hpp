#pragma once

#include <functional>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include <fastdds/rtps/common/Guid.h>
#include <fastdds/dds/domain/DomainParticipantListener.hpp>
#include <fastdds/rtps/common/GuidPrefix_t.hpp>

#include "base/time.hpp"
#include "passthrough/offered_qos.hpp"
#include "passthrough/type_object_guard.hpp"

namespace eprosima::fastrtps::types {
class TypeObject;
}  // namespace eprosima::fastrtps::types

namespace tgw::passthrough {

/// What the gateway learns about a publisher on the robot domain, from SEDP.
struct DiscoveredPublisher {
    std::string topic;
    std::string type_name;
    bool keyed = false;
    std::optional<base::Duration> lifespan;  ///< nullopt when the writer's Lifespan is infinite
    OfferedQos qos;
    eprosima::fastrtps::rtps::GUID_t writer;
    /// The complete XTypes TypeObject the writer announced with its type (a Fast DDS type with one registered);
    /// nullptr when it announced none, as most writers do. Fast DDS itself never sees it (TypeObjectGuard).
    std::shared_ptr<const eprosima::fastrtps::types::TypeObject> type_object;
};

/// `data`, a writer's discovery data, as a DiscoveredPublisher with `type_object` (take_type_object()).
DiscoveredPublisher discovered_publisher(const eprosima::fastrtps::rtps::WriterProxyData& data,
                                         std::shared_ptr<const eprosima::fastrtps::types::TypeObject> type_object);

/// The robot participant's listener: turns every publisher discovered on the robot domain, whenever it
/// appears, into a DiscoveredPublisher for `on_publisher`, and tells `on_gone` the topic and GUID of each that
/// leaves (deleted, or its participant gone). Publishers of the gateway's own participants are ignored. As a
/// TypeObjectGuard, it keeps every endpoint's TypeObject from Fast DDS and gives publishers' to `on_publisher`. Runs in
/// Fast DDS's discovery thread: the callbacks must return quickly and create or delete no entities.
class Discovery final : public TypeObjectGuard {
  public:
    using Callback = std::function<void(DiscoveredPublisher&&)>;
    using GoneCallback = std::function<void(const std::string& topic, const eprosima::fastrtps::rtps::GUID_t&)>;

    explicit Discovery(Callback on_publisher, GoneCallback on_gone = {});

    /// Publishers of this participant will not be reported (the gateway's own).
    void ignore_participant(const eprosima::fastrtps::rtps::GuidPrefix_t& prefix);

    /// Called for each participant discovered, but the ignored ones. Set it before the participant is made.
    void on_participant(std::function<void(const eprosima::fastrtps::rtps::GuidPrefix_t&)> callback) {
        on_participant_ = std::move(callback);
    }

    void on_participant_discovery(eprosima::fastdds::dds::DomainParticipant* participant,
                                  eprosima::fastrtps::rtps::ParticipantDiscoveryInfo&& info) override;

    void on_publisher_discovery(eprosima::fastdds::dds::DomainParticipant* participant,
                                eprosima::fastrtps::rtps::WriterDiscoveryInfo&& info) override;

  private:
    bool ignored(const eprosima::fastrtps::rtps::GuidPrefix_t& prefix) const;

    Callback on_publisher_;
    GoneCallback on_gone_;
    std::function<void(const eprosima::fastrtps::rtps::GuidPrefix_t&)> on_participant_;
    mutable std::mutex mutex_;
    std::vector<eprosima::fastrtps::rtps::GuidPrefix_t> ignored_;
};

}  // namespace tgw::passthrough
