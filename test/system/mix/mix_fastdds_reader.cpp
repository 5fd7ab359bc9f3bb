// A base-camp program as ROS 2 makes them with Fast DDS, reading what mix_pub publishes: a participant with every
// default (built-in transports, multicast discovery, no peers) and on each of the six topics a reliable reader,
// otherwise with Fast DDS's defaults (KEEP_LAST 1). MIX_BEST_EFFORT=1 makes the readers best effort, for the
// comparison run. It does not know the types: the passthrough type, registered under Cyclone's type names, hands
// over the serialized bytes, and the fields it needs are read from them.
//
//   mix_fastdds_reader DOMAIN SECONDS OUT_FILE
//
// Each valid sample appends "TOPIC SEQ SOURCE_NS ARRIVAL_NS INSTANCE" to OUT_FILE, as mix_sub does (wall-clock
// ns; INSTANCE the joint's id, -1 for unkeyed topics), flushed every second and at exit. Exits 0 after SECONDS or
// on SIGTERM/SIGINT.
#include <atomic>
#include <chrono>
#include <csignal>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

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

std::atomic<bool> stop_requested{false};

void on_signal(int /*signo*/) {
    stop_requested = true;
}

std::int64_t wall_clock_ns() {
    return std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::system_clock::now().time_since_epoch())
        .count();
}

/// The output file, shared by the readers' listeners.
class SampleLog {
  public:
    explicit SampleLog(std::FILE* out) : out_(out) {}

    void append(const std::string& topic, std::uint32_t seq, std::int64_t source_ns, std::int64_t arrival_ns,
                std::int32_t instance) {
        std::lock_guard<std::mutex> lock(mutex_);
        std::fprintf(out_, "%s %u %lld %lld %d\n", topic.c_str(), static_cast<unsigned>(seq),
                     static_cast<long long>(source_ns), static_cast<long long>(arrival_ns), static_cast<int>(instance));
    }

    void flush() {
        std::lock_guard<std::mutex> lock(mutex_);
        std::fflush(out_);
    }

  private:
    std::mutex mutex_;
    std::FILE* out_;
};

/// A 32-bit integer at `offset` of the CDR body (after the 4-byte encapsulation header), in the byte order the
/// header gives; false when the payload is shorter.
bool cdr_u32(const std::vector<std::uint8_t>& payload, std::size_t offset, std::uint32_t* value) {
    constexpr std::size_t ENCAPSULATION_BYTES = 4;
    if (payload.size() < ENCAPSULATION_BYTES + offset + 4) {
        return false;
    }
    const std::uint8_t* p = payload.data() + ENCAPSULATION_BYTES + offset;
    const bool little_endian = (payload[1] & 0x01) != 0;
    *value =
        little_endian
            ? (std::uint32_t{p[0]} | std::uint32_t{p[1]} << 8 | std::uint32_t{p[2]} << 16 | std::uint32_t{p[3]} << 24)
            : (std::uint32_t{p[3]} | std::uint32_t{p[2]} << 8 | std::uint32_t{p[1]} << 16 | std::uint32_t{p[0]} << 24);
    return true;
}

/// Where Joint's id lies in the CDR body: seq at 0, stamp_ns at 8 in XCDR1 (8-byte alignment, encapsulation
/// CDR_BE/CDR_LE, what Cyclone 0.10 writes for @final types), at 4 in XCDR2 (alignment at most 4), then id.
std::size_t joint_id_offset(const std::vector<std::uint8_t>& payload) {
    const bool xcdr1 = payload.size() >= 2 && payload[0] == 0x00 && payload[1] <= 0x01;
    return xcdr1 ? 16 : 12;
}

class MixListener final : public fdds::DataReaderListener {
  public:
    MixListener(std::string topic, bool keyed, SampleLog* log) : topic_(std::move(topic)), keyed_(keyed), log_(log) {}

    void on_data_available(fdds::DataReader* reader) override {
        tgw::passthrough::PassthroughData data;
        fdds::SampleInfo info;
        while (reader->take_next_sample(&data, &info) == ReturnCode_t::RETCODE_OK) {
            const std::int64_t arrival_ns = wall_clock_ns();
            std::uint32_t seq = 0;
            if (!info.valid_data || !cdr_u32(data.payload, 0, &seq)) {
                continue;
            }
            std::int32_t instance = -1;
            std::uint32_t id = 0;
            if (keyed_ && cdr_u32(data.payload, joint_id_offset(data.payload), &id)) {
                instance = static_cast<std::int32_t>(id);
            }
            log_->append(topic_, seq, info.source_timestamp.to_ns(), arrival_ns, instance);
            received_.fetch_add(1);
        }
    }

    const std::string& topic() const { return topic_; }
    unsigned long received() const { return received_.load(); }

  private:
    std::string topic_;
    bool keyed_;
    SampleLog* log_;
    std::atomic<unsigned long> received_{0};
};

struct MixTopic {
    const char* name;
    const char* type_name;
    bool keyed;
};

constexpr MixTopic TOPICS[] = {
    {"mix/hazard", "tgw_mix::Text", false}, {"mix/pose", "tgw_mix::Pose", false},
    {"mix/joints", "tgw_mix::Joint", true}, {"mix/battery", "tgw_mix::Text", false},
    {"mix/image", "tgw_mix::Blob", false},  {"mix/science", "tgw_mix::Blob", false},
};

}  // namespace

int main(int argc, char** argv) {
    const double seconds = argc == 4 ? std::atof(argv[2]) : 0.0;
    if (argc != 4 || seconds <= 0) {
        std::fprintf(stderr, "usage: mix_fastdds_reader DOMAIN SECONDS OUT_FILE\n");
        return 2;
    }
    const int domain = std::atoi(argv[1]);
    const char* best_effort_env = std::getenv("MIX_BEST_EFFORT");
    const bool best_effort = best_effort_env != nullptr && std::strcmp(best_effort_env, "1") == 0;

    std::FILE* out = std::fopen(argv[3], "a");
    if (out == nullptr) {
        std::fprintf(stderr, "mix_fastdds_reader: cannot open %s\n", argv[3]);
        return 1;
    }
    SampleLog log(out);
    auto* factory = fdds::DomainParticipantFactory::get_instance();
    fdds::DomainParticipant* participant = factory->create_participant(domain, fdds::PARTICIPANT_QOS_DEFAULT);
    if (participant == nullptr) {
        std::fprintf(stderr, "mix_fastdds_reader: cannot create a participant on domain %d\n", domain);
        std::fclose(out);
        return 1;
    }
    fdds::Subscriber* subscriber = participant->create_subscriber(fdds::SUBSCRIBER_QOS_DEFAULT);
    fdds::DataReaderQos qos = fdds::DATAREADER_QOS_DEFAULT;
    qos.reliability().kind = best_effort ? fdds::BEST_EFFORT_RELIABILITY_QOS : fdds::RELIABLE_RELIABILITY_QOS;
    std::vector<std::unique_ptr<MixListener>> listeners;
    std::vector<fdds::DataReader*> readers;
    for (const MixTopic& t : TOPICS) {
        fdds::Topic* topic = tgw::passthrough::passthrough_topic(participant, t.name, t.type_name, t.keyed);
        listeners.push_back(std::make_unique<MixListener>(t.name, t.keyed, &log));
        fdds::DataReader* reader =
            topic == nullptr ? nullptr : subscriber->create_datareader(topic, qos, listeners.back().get());
        if (reader == nullptr) {
            std::fprintf(stderr, "mix_fastdds_reader: cannot create the reader of %s\n", t.name);
            participant->delete_contained_entities();
            factory->delete_participant(participant);
            std::fclose(out);
            return 1;
        }
        readers.push_back(reader);
    }

    std::signal(SIGINT, on_signal);
    std::signal(SIGTERM, on_signal);
    const auto end = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
    auto next_flush = std::chrono::steady_clock::now() + std::chrono::seconds(1);
    while (!stop_requested && std::chrono::steady_clock::now() < end) {
        std::this_thread::sleep_for(std::chrono::milliseconds(50));
        if (std::chrono::steady_clock::now() >= next_flush) {
            log.flush();
            next_flush += std::chrono::seconds(1);
        }
    }

    for (fdds::DataReader* reader : readers) {
        reader->set_listener(nullptr);
    }
    participant->delete_contained_entities();
    factory->delete_participant(participant);
    std::fclose(out);
    for (const auto& listener : listeners) {
        std::printf("mix_fastdds_reader: %s received %lu\n", listener->topic().c_str(), listener->received());
    }
    return 0;
}
