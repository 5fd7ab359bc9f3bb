#pragma once

#include <fcntl.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <cstdint>
#include <functional>
#include <map>
#include <mutex>
#include <optional>
#include <set>
#include <string>
#include <thread>
#include <vector>

#include <fastdds/rtps/reader/ReaderDiscoveryInfo.h>
#include <fastdds/rtps/transport/UDPv4TransportDescriptor.h>
#include <fastdds/rtps/writer/WriterDiscoveryInfo.h>
#include <fastrtps/types/TypeObject.h>
#include <fastrtps/utils/IPLocator.h>
#include <fastrtps/xmlparser/XMLProfileManager.h>
#include <fastdds/dds/domain/DomainParticipant.hpp>
#include <fastdds/dds/domain/DomainParticipantFactory.hpp>
#include <fastdds/dds/domain/DomainParticipantListener.hpp>
#include <fastdds/dds/publisher/DataWriter.hpp>
#include <fastdds/dds/publisher/DataWriterListener.hpp>
#include <fastdds/dds/publisher/Publisher.hpp>
#include <fastdds/dds/subscriber/DataReader.hpp>
#include <fastdds/dds/subscriber/DataReaderListener.hpp>
#include <fastdds/dds/subscriber/SampleInfo.hpp>
#include <fastdds/dds/subscriber/Subscriber.hpp>
#include <fastdds/dds/topic/Topic.hpp>

#include "base/wan_address.hpp"

namespace tgw::test {

namespace fdds = eprosima::fastdds::dds;

/// Polls `condition` every 10 ms until it holds or `timeout` passes; true if it held.
inline bool wait_until(const std::function<bool()>& condition,
                       std::chrono::milliseconds timeout = std::chrono::seconds(10)) {
    const auto end = std::chrono::steady_clock::now() + timeout;
    while (!condition()) {
        if (std::chrono::steady_clock::now() >= end) {
            return false;
        }
        std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
    return true;
}

/// Makes participants of this process talk through their transports (shared memory, UDP) instead of Fast
/// DDS's in-process shortcut, so the tests see what separate processes would. Call before creating any.
inline void use_transports_in_process() {
    eprosima::fastrtps::LibrarySettingsAttributes settings;
    settings.intraprocess_delivery = eprosima::fastrtps::INTRAPROCESS_OFF;
    eprosima::fastrtps::xmlparser::XMLProfileManager::library_settings(settings);
}

/// A slot no other running test process holds, 0 .. SLOTS-1: each slot is a lock file under /tmp/tgw-test-domains
/// held (flock) until the process exits. The search starts at the process id's slot, so that consecutive tests do
/// not reuse the domains just let go of (Fast DDS's shared-memory ports outlive a process for a while). Process ids
/// alone gave two tests running side by side the same domains now and then: Fast DDS's threads use up ids, so
/// neighbours are often a multiple of SLOTS apart.
inline int test_slot() {
    static const int slot = [] {
        constexpr int SLOTS = 70;
        const char* dir = "/tmp/tgw-test-domains";
        ::mkdir(dir, 0777);
        const int first = static_cast<int>(::getpid() % SLOTS);
        for (int n = 0; n < SLOTS; ++n) {
            const int i = (first + n) % SLOTS;
            const std::string path = std::string(dir) + "/" + std::to_string(i) + ".lock";
            const int fd = ::open(path.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0666);
            if (fd >= 0 && ::flock(fd, LOCK_EX | LOCK_NB) == 0)
                return i;  // the descriptor stays open: the lock is the process's until it exits
            if (fd >= 0)
                ::close(fd);
        }
        return first;  // every slot taken: as before
    }();
    return slot;
}

/// Domain ids and ports for one test process, apart from every other test process running (test_slot()): a robot
/// domain in 10..79, a WAN domain in 85..154 and a base camp's own domain in 160..229. Not adjacent: a domain's
/// ports run into the next domain's from participant id 125 on, which the robot side's automatic ids reach when a
/// test repeats in one process, and the WAN side's fixed ports must never be among them.
struct TestDomains {
    int robot = 0;
    int wan = 0;
    int camp = 0;                        ///< a relay's camp-side domain
    std::uint16_t wan_reader_port = 0;   ///< the test's base-camp participant, the gateway's --wan-peer
    std::uint16_t gateway_wan_port = 0;  ///< the gateway's own WAN metatraffic port

    static TestDomains for_this_process() {
        TestDomains d;
        d.robot = 10 + test_slot();
        d.wan = 85 + test_slot();
        d.camp = 160 + test_slot();
        // Participant ids well above what Fast DDS assigns in one process, so the ports are free.
        d.wan_reader_port = base::metatraffic_unicast_port(d.wan, 60);
        d.gateway_wan_port = base::metatraffic_unicast_port(d.wan, 61);
        return d;
    }
};

/// A participant with one publisher and one subscriber; deletes everything it made.
class TestParticipant {
  public:
    TestParticipant(int domain, const fdds::DomainParticipantQos& qos,
                    fdds::DomainParticipantListener* listener = nullptr) {
        participant_ = fdds::DomainParticipantFactory::get_instance()->create_participant(
            static_cast<fdds::DomainId_t>(domain), qos, listener, fdds::StatusMask::none());
        if (participant_ != nullptr) {
            publisher_ = participant_->create_publisher(fdds::PUBLISHER_QOS_DEFAULT);
            subscriber_ = participant_->create_subscriber(fdds::SUBSCRIBER_QOS_DEFAULT);
        }
    }
    ~TestParticipant() {
        if (participant_ != nullptr) {
            participant_->delete_contained_entities();
            fdds::DomainParticipantFactory::get_instance()->delete_participant(participant_);
        }
    }
    TestParticipant(const TestParticipant&) = delete;
    TestParticipant& operator=(const TestParticipant&) = delete;

    bool ok() const { return participant_ != nullptr && publisher_ != nullptr && subscriber_ != nullptr; }
    fdds::DomainParticipant* participant() { return participant_; }

    /// A robot-side participant: Fast DDS defaults (shared memory, UDP, multicast), as a robot process has.
    static fdds::DomainParticipantQos robot_qos() { return fdds::PARTICIPANT_QOS_DEFAULT; }

    /// A base-camp participant on loopback only: UDPv4, no multicast, its metatraffic on `own_port`,
    /// announcing itself to `peer_port` (the gateway's WAN participant).
    static fdds::DomainParticipantQos wan_qos(std::uint16_t own_port, std::uint16_t peer_port) {
        using eprosima::fastrtps::rtps::IPLocator;
        using eprosima::fastrtps::rtps::Locator_t;
        fdds::DomainParticipantQos qos;
        qos.name("test/basecamp");
        qos.transport().use_builtin_transports = false;
        auto udp = std::make_shared<eprosima::fastdds::rtps::UDPv4TransportDescriptor>();
        udp->interfaceWhiteList.push_back("127.0.0.1");
        qos.transport().user_transports.push_back(udp);
        Locator_t own;
        own.kind = LOCATOR_KIND_UDPv4;
        IPLocator::setIPv4(own, "127.0.0.1");
        own.port = own_port;
        qos.wire_protocol().builtin.metatrafficUnicastLocatorList.push_back(own);
        Locator_t peer = own;
        peer.port = peer_port;
        qos.wire_protocol().builtin.initialPeersList.push_back(peer);
        return qos;
    }

    /// A writer in the default partition, or in `partitions` (through a publisher of its own).
    fdds::DataWriter* make_writer(const std::string& topic_name, fdds::TypeSupport type, fdds::DataWriterQos qos,
                                  fdds::DataWriterListener* listener = nullptr,
                                  const std::vector<std::string>& partitions = {}) {
        fdds::Topic* topic = topic_for(topic_name, type);
        fdds::Publisher* publisher = publisher_;
        if (!partitions.empty()) {
            fdds::PublisherQos pq = participant_->get_default_publisher_qos();
            for (const std::string& p : partitions) {
                pq.partition().push_back(p.c_str());
            }
            publisher = participant_->create_publisher(pq);
        }
        return topic == nullptr || publisher == nullptr
                   ? nullptr
                   : publisher->create_datawriter(topic, qos, listener, fdds::StatusMask::all());
    }

    /// A reader in the default partition, or in `partitions` (through a subscriber of its own).
    fdds::DataReader* make_reader(const std::string& topic_name, fdds::TypeSupport type, fdds::DataReaderQos qos,
                                  fdds::DataReaderListener* listener = nullptr,
                                  const std::vector<std::string>& partitions = {}) {
        fdds::Topic* topic = topic_for(topic_name, type);
        fdds::Subscriber* subscriber = subscriber_;
        if (!partitions.empty()) {
            fdds::SubscriberQos sq = participant_->get_default_subscriber_qos();
            for (const std::string& p : partitions) {
                sq.partition().push_back(p.c_str());
            }
            subscriber = participant_->create_subscriber(sq);
        }
        return topic == nullptr || subscriber == nullptr
                   ? nullptr
                   : subscriber->create_datareader(topic, qos, listener, fdds::StatusMask::all());
    }

    fdds::DataWriterQos default_writer_qos() const { return publisher_->get_default_datawriter_qos(); }
    fdds::DataReaderQos default_reader_qos() const { return subscriber_->get_default_datareader_qos(); }

  private:
    fdds::Topic* topic_for(const std::string& topic_name, fdds::TypeSupport type) {
        if (participant_->find_type(type.get_type_name()).empty()) {
            if (participant_->register_type(type) != ReturnCode_t::RETCODE_OK) {
                return nullptr;
            }
        }
        if (auto* existing = participant_->find_topic(topic_name, eprosima::fastrtps::Duration_t(0, 0))) {
            return existing;
        }
        return participant_->create_topic(topic_name, type.get_type_name(), fdds::TOPIC_QOS_DEFAULT);
    }

    fdds::DomainParticipant* participant_ = nullptr;
    fdds::Publisher* publisher_ = nullptr;
    fdds::Subscriber* subscriber_ = nullptr;
};

/// Counts matches of a writer.
class MatchCounter final : public fdds::DataWriterListener {
  public:
    void on_publication_matched(fdds::DataWriter*, const fdds::PublicationMatchedStatus& info) override {
        matched = info.current_count;
    }
    std::atomic<int> matched{0};
};

/// Takes every sample of type T a reader receives, with its SampleInfo.
template <typename T>
class CollectingReader final : public fdds::DataReaderListener {
  public:
    struct Received {
        T data;
        fdds::SampleInfo info;
    };

    void on_data_available(fdds::DataReader* reader) override {
        // Held from take to record: two receive threads may call this at once, and without it one could record
        // a later sample before the other records the earlier one it took.
        std::lock_guard<std::mutex> order(take_order_);
        T data;
        fdds::SampleInfo info;
        while (reader->take_next_sample(&data, &info) == ReturnCode_t::RETCODE_OK) {
            std::lock_guard<std::mutex> lock(mutex_);
            if (info.valid_data) {
                received_.push_back({data, info});
            } else if (info.instance_state == fdds::NOT_ALIVE_DISPOSED_INSTANCE_STATE) {
                disposed_.insert(info.instance_handle);
            } else if (info.instance_state == fdds::NOT_ALIVE_NO_WRITERS_INSTANCE_STATE) {
                unregistered_.insert(info.instance_handle);
            }
        }
    }
    void on_subscription_matched(fdds::DataReader*, const fdds::SubscriptionMatchedStatus& info) override {
        matched = info.current_count;
    }

    std::size_t count() const {
        std::lock_guard<std::mutex> lock(mutex_);
        return received_.size();
    }
    std::vector<Received> received() const {
        std::lock_guard<std::mutex> lock(mutex_);
        return received_;
    }
    /// Instances that arrived disposed.
    std::set<fdds::InstanceHandle_t> disposed() const {
        std::lock_guard<std::mutex> lock(mutex_);
        return disposed_;
    }

    /// Instances that arrived with no writer left (unregistered by the last one).
    std::set<fdds::InstanceHandle_t> unregistered() const {
        std::lock_guard<std::mutex> lock(mutex_);
        return unregistered_;
    }

    std::atomic<int> matched{0};

  private:
    std::mutex take_order_;
    mutable std::mutex mutex_;
    std::vector<Received> received_;
    std::set<fdds::InstanceHandle_t> disposed_;
    std::set<fdds::InstanceHandle_t> unregistered_;
};

/// Records the WAN writers the base camp discovers, with their Lifespan.
class PublisherWatcher final : public fdds::DomainParticipantListener {
  public:
    void on_publisher_discovery(fdds::DomainParticipant*,
                                eprosima::fastrtps::rtps::WriterDiscoveryInfo&& info) override {
        if (info.status != eprosima::fastrtps::rtps::WriterDiscoveryInfo::DISCOVERED_WRITER) {
            return;
        }
        std::shared_ptr<const eprosima::fastrtps::types::TypeObject> type_object;
        if (info.info.has_type() && info.info.type().m_type_object._d() == eprosima::fastrtps::types::EK_COMPLETE)
            type_object = std::make_shared<eprosima::fastrtps::types::TypeObject>(info.info.type().m_type_object);
        std::lock_guard<std::mutex> lock(mutex_);
        seen_.push_back(
            {info.info.topicName().to_string(), info.info.typeName().to_string(), info.info.m_qos.m_lifespan.duration,
             info.info.m_qos.m_reliability.kind, info.info.m_qos.m_durability.kind, info.info.m_qos.m_ownership.kind,
             info.info.m_qos.m_ownershipStrength.value, info.info.m_qos.m_partition.names(), std::move(type_object)});
    }

    struct Seen {
        std::string topic;
        std::string type_name;
        eprosima::fastrtps::Duration_t lifespan;
        fdds::ReliabilityQosPolicyKind reliability;
        fdds::DurabilityQosPolicyKind durability;
        fdds::OwnershipQosPolicyKind ownership;
        std::uint32_t ownership_strength;
        std::vector<std::string> partitions;
        std::shared_ptr<const eprosima::fastrtps::types::TypeObject> type_object;  ///< a complete one, if announced
    };

    bool find(const std::string& topic, Seen& out) const {
        std::lock_guard<std::mutex> lock(mutex_);
        for (const Seen& s : seen_) {
            if (s.topic == topic) {
                out = s;
                return true;
            }
        }
        return false;
    }

  private:
    mutable std::mutex mutex_;
    std::vector<Seen> seen_;
};

/// Records the locator kinds each discovered reader offers, by topic.
class ReaderLocatorWatcher final : public fdds::DomainParticipantListener {
  public:
    void on_subscriber_discovery(fdds::DomainParticipant*,
                                 eprosima::fastrtps::rtps::ReaderDiscoveryInfo&& info) override {
        if (info.status != eprosima::fastrtps::rtps::ReaderDiscoveryInfo::DISCOVERED_READER) {
            return;
        }
        std::lock_guard<std::mutex> lock(mutex_);
        auto& kinds = kinds_[info.info.topicName().to_string()];
        for (const auto& locator : info.info.remote_locators().unicast) {
            kinds.insert(locator.kind);
        }
    }

    std::optional<std::set<std::int32_t>> kinds(const std::string& topic) const {
        std::lock_guard<std::mutex> lock(mutex_);
        const auto it = kinds_.find(topic);
        return it == kinds_.end() ? std::nullopt : std::optional<std::set<std::int32_t>>(it->second);
    }

  private:
    mutable std::mutex mutex_;
    std::map<std::string, std::set<std::int32_t>> kinds_;
};

}  // namespace tgw::test
