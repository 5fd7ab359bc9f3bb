#pragma once

// Payloads for the decoder's tests, and a look-up of decoded members by name: the fastddsgen-generated types of the
// project serialized by Fast-CDR in either byte order (XCDR1, as Fast DDS 2.9 writes them), and a small writer for
// hand-made XCDR2 payloads, which Fast-CDR 1.0 cannot write.
#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

#include <fastcdr/Cdr.h>
#include <fastcdr/FastBuffer.h>

#include "types/decoded_value.hpp"

namespace tgw::test {

/// The member `name` of a decoded record; a static empty record when it has none (the test then fails on it).
inline const types::DecodedValue& member(const types::DecodedValue& record, const std::string& name) {
    for (const auto& [field, value] : record.fields) {
        if (field == name)
            return value;
    }
    static const types::DecodedValue missing;
    return missing;
}

/// `sample` (a fastddsgen type) as a DDS payload: the encapsulation header, then the sample in `endianness`.
template <typename Sample>
std::vector<std::uint8_t> fastcdr_payload(const Sample& sample, eprosima::fastcdr::Cdr::Endianness endianness) {
    std::vector<char> buffer(Sample::getCdrSerializedSize(sample) + 64);
    eprosima::fastcdr::FastBuffer fast(buffer.data(), buffer.size());
    eprosima::fastcdr::Cdr cdr(fast, endianness, eprosima::fastcdr::Cdr::DDS_CDR);
    cdr.serialize_encapsulation();
    sample.serialize(cdr);
    const auto* bytes = reinterpret_cast<const std::uint8_t*>(buffer.data());
    return std::vector<std::uint8_t>(bytes, bytes + cdr.getSerializedDataLength());
}

/// Writes CDR by hand: XCDR1 aligns to the size (8 for 64-bit), XCDR2 to 4 at most, both from the first byte
/// after the encapsulation header.
class CdrWriter {
  public:
    CdrWriter(std::uint16_t encapsulation, bool little_endian, bool xcdr2)
        : little_endian_(little_endian), xcdr2_(xcdr2) {
        bytes_ = {static_cast<std::uint8_t>(encapsulation >> 8), static_cast<std::uint8_t>(encapsulation), 0, 0};
    }

    CdrWriter& u8(std::uint8_t v) { return put(v, 1); }
    CdrWriter& u16(std::uint16_t v) { return put(v, 2); }
    CdrWriter& u32(std::uint32_t v) { return put(v, 4); }
    CdrWriter& u64(std::uint64_t v) { return put(v, 8); }
    CdrWriter& f64(double v) {
        std::uint64_t bits = 0;
        std::memcpy(&bits, &v, sizeof v);
        return put(bits, 8);
    }
    CdrWriter& str(const std::string& s) {
        u32(static_cast<std::uint32_t>(s.size() + 1));
        bytes_.insert(bytes_.end(), s.begin(), s.end());
        bytes_.push_back(0);
        return *this;
    }

    /// Starts a DHEADER; end_dheader() fills in the size of what was written after it.
    std::size_t begin_dheader() {
        u32(0);
        return bytes_.size();
    }
    CdrWriter& end_dheader(std::size_t start) {
        const auto size = static_cast<std::uint32_t>(bytes_.size() - start);
        const std::size_t at = start - 4;
        for (std::size_t i = 0; i < 4; ++i)
            bytes_[at + i] = static_cast<std::uint8_t>(size >> (8 * (little_endian_ ? i : 3 - i)));
        return *this;
    }

    const std::vector<std::uint8_t>& bytes() const { return bytes_; }

  private:
    CdrWriter& put(std::uint64_t v, std::size_t size) {
        const std::size_t alignment = xcdr2_ && size > 4 ? 4 : size;
        while ((bytes_.size() - 4) % alignment != 0)
            bytes_.push_back(0);
        for (std::size_t i = 0; i < size; ++i)
            bytes_.push_back(static_cast<std::uint8_t>(v >> (8 * (little_endian_ ? i : size - 1 - i))));
        return *this;
    }

    bool little_endian_;
    bool xcdr2_;
    std::vector<std::uint8_t> bytes_;
};

}  // namespace tgw::test
