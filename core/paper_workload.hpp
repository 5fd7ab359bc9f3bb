#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "base/time.hpp"

namespace tgw::core {

/// One periodic message stream of a workload: a topic whose samples carry `data_bytes` of payload data.
struct MessageStream {
    std::string type;   ///< short name used in tables: "A"
    std::string topic;  ///< DDS topic: "telemetry/A"
    std::size_t data_bytes = 0;
    base::Duration ttl{};
    double rate_hz = 5.0;
};

/// The 2001 paper's four message types (docs/design.md §2): 41, 66, 266 and 1016 bytes, TTL 1, 2, 5, 20 s,
/// 5 Hz each.
std::vector<MessageStream> paper_workload(double rate_hz = 5.0);

/// Serialized size of a PaperMessage (idl/PaperWorkload.idl) carrying `data_bytes`, as CDR with its
/// 4-byte encapsulation header: what the gateway sees as payload.
std::size_t paper_message_serialized_bytes(std::size_t data_bytes);

}  // namespace tgw::core
