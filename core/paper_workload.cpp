#include "core/paper_workload.hpp"

namespace tgw::core {

std::vector<MessageStream> paper_workload(double rate_hz) {
    using std::chrono::seconds;
    return {
        {"A", "telemetry/A", 41, seconds(1), rate_hz},
        {"B", "telemetry/B", 66, seconds(2), rate_hz},
        {"C", "telemetry/C", 266, seconds(5), rate_hz},
        {"D", "telemetry/D", 1016, seconds(20), rate_hz},
    };
}

std::size_t paper_message_serialized_bytes(std::size_t data_bytes) {
    // encapsulation 4 + generated_ns 8 + sequence 4 + length 4 + data; Fast DDS pads the payload to 4.
    const std::size_t raw = 4 + 8 + 4 + 4 + data_bytes;
    return (raw + 3u) & ~std::size_t{3u};
}

}  // namespace tgw::core
