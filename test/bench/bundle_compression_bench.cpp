// What zstd saves on compact-mode bundles (issue 19), for three kinds of telemetry: the paper's workload with
// random data (as a real sensor's bytes would be: they do not compress), the same with tm-robot-sim's counting
// bytes (0, 1, 2, ...: they do), and a realistic mix of small typed samples (keyed readings with repeated labels,
// poses, status strings). Each bundle holds what the scheduler packs into one datagram (1,300 encoded bytes at
// most). Prints, per kind of 2,000 samples, the bundles' bytes uncompressed and with --wan-compress, and the ratio.
#include <cstdio>
#include <random>
#include <string>
#include <vector>

#include <fastcdr/Cdr.h>
#include <fastcdr/FastBuffer.h>

#include "KeyedReading.h"
#include "PaperWorkload.h"
#include "RobotPose.h"
#include "RosString.h"
#include "compact/bundle_codec.hpp"
#include "core/bundle_builder.hpp"
#include "core/paper_workload.hpp"

namespace {

using tgw::compact::Bundle;
using tgw::compact::BundleCodec;
using tgw::compact::BundleCompression;
using tgw::compact::BundleEntry;

template <typename T>
std::vector<std::uint8_t> cdr(const T& value) {
    std::vector<char> buffer(8192);
    eprosima::fastcdr::FastBuffer fast(buffer.data(), buffer.size());
    eprosima::fastcdr::Cdr out(fast, eprosima::fastcdr::Cdr::DEFAULT_ENDIAN, eprosima::fastcdr::Cdr::DDS_CDR);
    out.serialize_encapsulation();
    value.serialize(out);
    return {buffer.begin(), buffer.begin() + static_cast<std::ptrdiff_t>(out.getSerializedDataLength())};
}

/// Packs `samples` (topic id, payload) in order into bundles of at most one datagram, as the scheduler does.
std::vector<Bundle> pack(const std::vector<std::pair<std::uint32_t, std::vector<std::uint8_t>>>& samples) {
    const std::size_t max_bytes = tgw::core::BundleLimits{}.max_encoded_bytes;
    std::vector<Bundle> bundles(1);
    std::size_t bytes = BundleCodec::MAX_FRAME_BYTES;
    std::int64_t t = 1'790'000'000'000'000'000;
    for (const auto& [topic, payload] : samples) {
        t += 50'000'000;
        const std::size_t entry =
            BundleCodec::entry_bytes(topic, 0, 50'000'000, payload.size(),
                                     BundleCodec::plain_cdr(payload.data(), payload.size()), false, nullptr);
        if (bytes + entry > max_bytes && !bundles.back().entries.empty()) {
            bundles.emplace_back();
            bytes = BundleCodec::MAX_FRAME_BYTES;
        }
        BundleEntry e;
        e.topic_id = topic;
        e.source_ns = t;
        e.payload = payload;
        bundles.back().entries.push_back(std::move(e));
        bytes += entry;
    }
    return bundles;
}

void report(const char* kind, const std::vector<Bundle>& bundles) {
    std::size_t plain = 0, compressed = 0;
    std::vector<std::uint8_t> out;
    for (const Bundle& b : bundles) {
        BundleCodec::encode(b, out, BundleCompression::none);
        plain += out.size();
        BundleCodec::encode(b, out, BundleCompression::zstd_if_smaller);
        compressed += out.size();
    }
    std::printf("| %s | %zu | %zu | %zu | %.2f |\n", kind, bundles.size(), plain, compressed,
                static_cast<double>(plain) / static_cast<double>(compressed));
}

std::vector<std::pair<std::uint32_t, std::vector<std::uint8_t>>> paper(bool random_data) {
    std::mt19937 rng(1);
    std::vector<std::pair<std::uint32_t, std::vector<std::uint8_t>>> samples;
    const auto workload = tgw::core::paper_workload();
    for (std::uint32_t n = 0; samples.size() < 2'000; ++n) {
        const auto type = n % workload.size();
        tgw::idl::PaperMessage m;
        m.generated_ns(n);
        std::vector<std::uint8_t> data(workload[type].data_bytes);
        for (std::size_t b = 0; b < data.size(); ++b)
            data[b] = random_data ? static_cast<std::uint8_t>(rng()) : static_cast<std::uint8_t>(b);
        m.data(data);
        samples.emplace_back(static_cast<std::uint32_t>(type), cdr(m));
    }
    return samples;
}

std::vector<std::pair<std::uint32_t, std::vector<std::uint8_t>>> typed_mix() {
    std::mt19937 rng(2);
    std::normal_distribution<double> noise(0.0, 0.01);
    const char* labels[] = {"imu/accel_x",     "imu/accel_y",   "imu/accel_z",  "wheel/left_rpm",
                            "wheel/right_rpm", "battery/volts", "battery/amps", "motor/temp_c"};
    std::vector<std::pair<std::uint32_t, std::vector<std::uint8_t>>> samples;
    double x = 12.0, y = -3.5, heading = 0.3;
    for (std::uint32_t n = 0; samples.size() < 2'000; ++n) {
        switch (n % 4) {
            case 0:
            case 1: {
                tgw::idl::KeyedReading r;
                r.sensor_id(n % 8);
                r.value(20.0 + (n % 8) + noise(rng));
                r.label(labels[n % 8]);
                samples.emplace_back(0, cdr(r));
                break;
            }
            case 2: {
                x += 0.05 + noise(rng);
                y += 0.01 + noise(rng);
                heading += noise(rng);
                tgw::idl::RobotPose p;
                p.x(x);
                p.y(y);
                p.heading_rad(heading);
                samples.emplace_back(1, cdr(p));
                break;
            }
            default: {
                std_msgs::msg::dds_::String_ s;
                s.data("battery " + std::to_string(87 - n / 400) + " %, mode AUTONOMOUS, waypoint " +
                       std::to_string(n / 100));
                samples.emplace_back(2, cdr(s));
                break;
            }
        }
    }
    return samples;
}

}  // namespace

int main() {
    std::printf("| samples (2,000 each) | bundles | bytes uncompressed | bytes with --wan-compress | ratio |\n");
    std::printf("|---|---:|---:|---:|---:|\n");
    report("paper workload, random data", pack(paper(true)));
    report("paper workload, tm-robot-sim's counting bytes", pack(paper(false)));
    report("typed mix: keyed readings, poses, status strings", pack(typed_mix()));
    return 0;
}
