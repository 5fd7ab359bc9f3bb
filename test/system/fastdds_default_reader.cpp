// A base-camp program as a newcomer writes it with Fast DDS: a participant with every default (shared memory,
// UDP, multicast discovery, no peers configured) and a reliable reader, as ROS 2 makes them. It reads the
// cross-vendor test's tgw_xv::Blob samples without knowing the type (their sequence number is the first field
// after the encapsulation header) and exits 0 once it has seen COUNT distinct ones, 1 after SECONDS without.
//
//   fastdds_default_reader DOMAIN TOPIC TYPE_NAME COUNT SECONDS
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <mutex>
#include <set>
#include <string>
#include <thread>

#include <fastdds/dds/domain/DomainParticipant.hpp>
#include <fastdds/dds/domain/DomainParticipantFactory.hpp>
#include <fastdds/dds/subscriber/DataReader.hpp>
#include <fastdds/dds/subscriber/DataReaderListener.hpp>
#include <fastdds/dds/subscriber/SampleInfo.hpp>
#include <fastdds/dds/subscriber/Subscriber.hpp>
#include <fastdds/dds/topic/Topic.hpp>

#include "passthrough/passthrough_type.hpp"

namespace fdds = eprosima::fastdds::dds;

namespace {

class SeqCollector final : public fdds::DataReaderListener {
  public:
    void on_data_available(fdds::DataReader* reader) override {
        tgw::passthrough::PassthroughData data;
        fdds::SampleInfo info;
        while (reader->take_next_sample(&data, &info) == ReturnCode_t::RETCODE_OK) {
            if (!info.valid_data || data.payload.size() < 8) {
                continue;
            }
            std::uint32_t seq = 0;
            std::memcpy(&seq, data.payload.data() + 4, sizeof seq);  // little endian, as Cyclone writes here
            std::lock_guard<std::mutex> lock(mutex_);
            seen_.insert(seq);
        }
    }

    std::size_t distinct() const {
        std::lock_guard<std::mutex> lock(mutex_);
        return seen_.size();
    }

  private:
    mutable std::mutex mutex_;
    std::set<std::uint32_t> seen_;
};

}  // namespace

int main(int argc, char** argv) {
    if (argc != 6) {
        std::fprintf(stderr, "usage: fastdds_default_reader DOMAIN TOPIC TYPE_NAME COUNT SECONDS\n");
        return 2;
    }
    const int domain = std::atoi(argv[1]);
    const std::string topic_name = argv[2];
    const std::string type_name = argv[3];
    const std::size_t count = std::strtoul(argv[4], nullptr, 10);
    const double seconds = std::atof(argv[5]);

    auto* factory = fdds::DomainParticipantFactory::get_instance();
    fdds::DomainParticipant* participant = factory->create_participant(domain, fdds::PARTICIPANT_QOS_DEFAULT);
    if (participant == nullptr) {
        std::fprintf(stderr, "fastdds_default_reader: cannot create a participant on domain %d\n", domain);
        return 1;
    }
    fdds::TypeSupport type(new tgw::passthrough::PassthroughType(type_name, false));
    type.register_type(participant);
    fdds::Topic* topic = participant->create_topic(topic_name, type_name, fdds::TOPIC_QOS_DEFAULT);
    fdds::Subscriber* subscriber = participant->create_subscriber(fdds::SUBSCRIBER_QOS_DEFAULT);
    fdds::DataReaderQos qos = fdds::DATAREADER_QOS_DEFAULT;
    qos.reliability().kind = fdds::RELIABLE_RELIABILITY_QOS;
    qos.history().depth = 100;
    SeqCollector collector;
    fdds::DataReader* reader = subscriber->create_datareader(topic, qos, &collector);
    if (reader == nullptr) {
        std::fprintf(stderr, "fastdds_default_reader: cannot create the reader of %s\n", topic_name.c_str());
        return 1;
    }

    const auto end = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
    while (collector.distinct() < count && std::chrono::steady_clock::now() < end) {
        std::this_thread::sleep_for(std::chrono::milliseconds(50));
    }
    const std::size_t got = collector.distinct();
    std::printf("fastdds_default_reader: %zu of %zu distinct samples of %s\n", got, count, topic_name.c_str());
    reader->set_listener(nullptr);
    participant->delete_contained_entities();
    factory->delete_participant(participant);
    return got >= count ? 0 : 1;
}
