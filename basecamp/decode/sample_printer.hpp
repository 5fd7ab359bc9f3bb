// How `tm-basecamp echo` prints one sample: its source time and instance, then its members decoded from the IDL
// of its type, or its size and bytes in hex when it cannot be decoded.
#pragma once

#include <cstdint>
#include <optional>
#include <ostream>
#include <string>
#include <vector>

#include "base/time.hpp"
#include "types/type_library.hpp"

namespace tgw::basecamp {

/// One sample as it came off the wire.
struct ReceivedSample {
    std::vector<std::uint8_t> payload;     ///< serialized, encapsulation header first
    std::optional<base::WallTime> source;  ///< the writer's source timestamp; nullopt when it sent none
    std::string instance;                  ///< keyed topics: the instance's key hash in hex; empty otherwise
};

/// Prints the samples of one type (SamplePrinter::Format): decoded with the IDL of `types`, else size and hex.
class SamplePrinter {
  public:
    enum class Format {
        text,  ///< YAML-like, one member a line, "---" after each sample (ros2 topic echo)
        json,  ///< one JSON object a line: {"source_timestamp_ns":..,"instance":..,"data":{..}}, or
               ///< {..,"size_bytes":N,"hex":"..","error":".."} when the sample cannot be decoded
    };

    /// `types` must outlive the printer.
    SamplePrinter(const types::TypeLibrary& types, std::string type_name, Format format);

    /// Writes `sample`; never throws on any payload.
    void print(std::ostream& out, const ReceivedSample& sample) const;

  private:
    const types::TypeLibrary& types_;
    const std::string type_name_;
    const Format format_;
};

/// `bytes` as lower-case hex digits, two a byte, without separators.
std::string hex_text(const std::uint8_t* bytes, std::size_t size);

}  // namespace tgw::basecamp
