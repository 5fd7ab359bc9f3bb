#include "gateway/dds/repeat_throttle.hpp"

#include <algorithm>
#include <cstring>

#include "wire/rtps_submessage.hpp"

namespace tgw::dds {

namespace {

using namespace wire::rtps_bytes;

/// Entries kept before old ones are swept: a few per matched reader and writer.
constexpr std::size_t SWEEP_ABOVE = 1024;

/// ENTITYID_P2P_BUILTIN_PARTICIPANT_STATELESS_WRITER (DDS Security 1.1, 7.4.3): its DATA carry the
/// authentication handshake.
constexpr std::uint8_t STATELESS_WRITER_ID[4] = {0x00, 0x02, 0x01, 0xc3};
/// A DATA's extraFlags, octetsToInlineQos, readerId, writerId and writerSN (DDSI-RTPS 9.4.5.3).
constexpr std::size_t DATA_HEADER_BYTES = 2 + 2 + 4 + 4 + 8;

/// FNV-1a, for keys of a few dozen bytes.
class Fnv1a {
  public:
    explicit Fnv1a(std::uint64_t seed = 0) : h_(OFFSET_BASIS ^ seed) {}
    void mix(const void* data, std::size_t n) {
        const auto* bytes = static_cast<const std::uint8_t*>(data);
        for (std::size_t i = 0; i < n; ++i) {
            h_ = (h_ ^ bytes[i]) * PRIME;
        }
    }
    std::uint64_t value() const { return h_; }

  private:
    static constexpr std::uint64_t OFFSET_BASIS = 1469598103934665603ull;
    static constexpr std::uint64_t PRIME = 1099511628211ull;
    std::uint64_t h_;
};

std::uint64_t destination_hash(const DatagramDestination& destination) {
    Fnv1a h(reinterpret_cast<std::uintptr_t>(destination.channel));
    for (const auto& locator : destination.locators) {
        h.mix(&locator.kind, sizeof(locator.kind));
        h.mix(&locator.port, sizeof(locator.port));
        h.mix(locator.address, sizeof(locator.address));
    }
    return h.value();
}

}  // namespace

bool RepeatThrottle::Key::operator==(const Key& other) const {
    return destination == other.destination && kind == other.kind && length == other.length &&
           std::memcmp(reader_prefix, other.reader_prefix, sizeof(reader_prefix)) == 0 &&
           std::memcmp(body, other.body, length) == 0;
}

std::size_t RepeatThrottle::KeyHash::operator()(const Key& key) const {
    Fnv1a h(key.destination);
    h.mix(key.reader_prefix, sizeof(key.reader_prefix));
    h.mix(&key.kind, sizeof(key.kind));
    h.mix(key.body, key.length);
    return static_cast<std::size_t>(h.value());
}

bool RepeatThrottle::lone_repeatable(const std::uint8_t* message, std::size_t size, Key& key) {
    if (size < MESSAGE_HEADER_BYTES || std::memcmp(message, "RTPS", 4) != 0) {
        return false;
    }
    key = Key{};
    std::size_t pos = MESSAGE_HEADER_BYTES;
    while (pos + SUBMESSAGE_HEADER_BYTES <= size) {
        const std::uint8_t* sub = message + pos;
        const std::size_t length = octets_to_next_header(sub);
        const std::uint8_t* body = sub + SUBMESSAGE_HEADER_BYTES;
        if (pos + SUBMESSAGE_HEADER_BYTES + length > size) {
            return false;
        }
        switch (sub[0]) {
            case INFO_DST:
                if (length < sizeof(key.reader_prefix)) {
                    return false;
                }
                std::memcpy(key.reader_prefix, body, sizeof(key.reader_prefix));
                break;
            case HEARTBEAT:
            case ACKNACK:
                // One per message, and its count (the last 4 bytes) is all that may differ from a repeat.
                if (key.kind != 0 || length < 4 + 4 + 4 || length - 4 > MAX_REPEAT_BYTES) {
                    return false;
                }
                key.kind = sub[0];
                key.length = static_cast<std::uint8_t>(length - 4);
                std::memcpy(key.body, body, key.length);
                break;
            case DATA: {
                // A handshake message (the same payload again under a new sequence number), or an announcement.
                const std::size_t data_length = length == 0 ? size - pos - SUBMESSAGE_HEADER_BYTES : length;
                if (key.kind != 0 || data_length < DATA_HEADER_BYTES ||
                    (std::memcmp(body + 8, STATELESS_WRITER_ID, sizeof(STATELESS_WRITER_ID)) != 0 &&
                     std::memcmp(body + 8, SPDP_WRITER_ID, sizeof(SPDP_WRITER_ID)) != 0)) {
                    return false;
                }
                key.kind = DATA;
                std::memcpy(key.body, body + 4, 8);  // reader and writer ids
                Fnv1a h;
                h.mix(body + DATA_HEADER_BYTES, data_length - DATA_HEADER_BYTES);
                const std::uint64_t payload_hash = h.value();
                std::memcpy(key.body + 8, &payload_hash, sizeof(payload_hash));
                key.length = 8 + sizeof(payload_hash);
                break;
            }
            case INFO_TS:
                // Only around a handshake message or an announcement, which their writers time-stamp.
                break;
            case EPROSIMA_STATISTICS:
                break;
            default:
                return false;
        }
        if (length == 0) {
            break;  // the submessage runs to the end of the message
        }
        pos += SUBMESSAGE_HEADER_BYTES + length;
    }
    return key.kind != 0;
}

bool RepeatThrottle::admit(const DatagramDestination& destination, const std::uint8_t* message, std::size_t size,
                           base::SteadyTime now) {
    Key key;
    if (!lone_repeatable(message, size, key)) {
        return true;
    }
    key.destination = destination_hash(destination);  // only for the few messages that are lone HEARTBEATs or ACKNACKs
    base::Duration interval = interval_;
    if (key.kind == DATA) {
        const bool announcement = std::memcmp(key.body + 4, SPDP_WRITER_ID, sizeof(SPDP_WRITER_ID)) == 0;
        interval = announcement ? announcement_interval_ : handshake_interval_;
    }
    std::lock_guard<std::mutex> lock(mutex_);
    auto [it, inserted] = last_sent_.try_emplace(key, now);
    if (!inserted) {
        if (now - it->second < interval) {
            ++suppressed_;
            return false;
        }
        it->second = now;
    }
    if (last_sent_.size() > SWEEP_ABOVE) {
        for (auto entry = last_sent_.begin(); entry != last_sent_.end();) {
            entry = now - entry->second >= std::max(interval_, handshake_interval_) ? last_sent_.erase(entry)
                                                                                    : std::next(entry);
        }
    }
    return true;
}

std::uint64_t RepeatThrottle::suppressed() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return suppressed_;
}

}  // namespace tgw::dds
