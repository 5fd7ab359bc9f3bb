#include "gateway/dds/heartbeat_throttle.hpp"

#include <cstring>

#include "gateway/dds/rtps_submessage.hpp"

namespace tgw::dds {

namespace {

using namespace rtps_bytes;

/// Entries kept before old ones are swept: a few per matched reader and writer.
constexpr std::size_t SWEEP_ABOVE = 1024;

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

bool HeartbeatThrottle::Key::operator==(const Key& other) const {
    return destination == other.destination &&
           std::memcmp(reader_prefix, other.reader_prefix, sizeof(reader_prefix)) == 0 &&
           std::memcmp(heartbeat, other.heartbeat, sizeof(heartbeat)) == 0;
}

std::size_t HeartbeatThrottle::KeyHash::operator()(const Key& key) const {
    Fnv1a h(key.destination);
    h.mix(key.reader_prefix, sizeof(key.reader_prefix));
    h.mix(key.heartbeat, sizeof(key.heartbeat));
    return static_cast<std::size_t>(h.value());
}

bool HeartbeatThrottle::lone_heartbeat(const std::uint8_t* message, std::size_t size, Key& key) {
    if (size < MESSAGE_HEADER_BYTES || std::memcmp(message, "RTPS", 4) != 0) {
        return false;
    }
    key = Key{};
    bool heartbeat = false;
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
                if (heartbeat || length < sizeof(key.heartbeat)) {
                    return false;
                }
                std::memcpy(key.heartbeat, body, sizeof(key.heartbeat));
                heartbeat = true;
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
    return heartbeat;
}

bool HeartbeatThrottle::admit(const DatagramDestination& destination, const std::uint8_t* message, std::size_t size,
                              base::SteadyTime now) {
    Key key;
    if (!lone_heartbeat(message, size, key)) {
        return true;
    }
    key.destination = destination_hash(destination);  // only for the few messages that are lone HEARTBEATs
    std::lock_guard<std::mutex> lock(mutex_);
    auto [it, inserted] = last_sent_.try_emplace(key, now);
    if (!inserted) {
        if (now - it->second < interval_) {
            ++suppressed_;
            return false;
        }
        it->second = now;
    }
    if (last_sent_.size() > SWEEP_ABOVE) {
        for (auto entry = last_sent_.begin(); entry != last_sent_.end();) {
            entry = now - entry->second >= interval_ ? last_sent_.erase(entry) : std::next(entry);
        }
    }
    return true;
}

std::uint64_t HeartbeatThrottle::suppressed() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return suppressed_;
}

}  // namespace tgw::dds
