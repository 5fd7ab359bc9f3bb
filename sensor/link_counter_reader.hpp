#pragma once

#include <cstdint>
#include <string>

#include "sensor/netlink_handles.hpp"

namespace tgw::sensor {

/// The kernel's side of a LinkCounters sample: what the interface sent and what its root qdisc dropped and holds.
struct KernelCounters {
    std::uint64_t tx_bytes = 0;       ///< the interface's transmit byte counter
    std::uint64_t drops = 0;          ///< packets the root qdisc dropped; 0 without a root qdisc
    std::uint64_t backlog_bytes = 0;  ///< bytes queued in the root qdisc now; 0 without one
};

struct KernelCountersReading {
    bool ok = false;
    KernelCounters counters;
    std::string error;  ///< when !ok, naming the interface
};

/// Reads an interface's transmit counter and its root qdisc's drop and backlog counters through rtnetlink, for
/// the delivered-rate check. Reads the network namespace of the thread that built it. Not thread-safe.
class LinkCounterReader {
  public:
    /// Throws base::ConfigError naming the interface when it does not exist.
    explicit LinkCounterReader(std::string interface);
    ~LinkCounterReader();

    LinkCounterReader(const LinkCounterReader&) = delete;
    LinkCounterReader& operator=(const LinkCounterReader&) = delete;

    /// Never throws; fails (ok false) when the interface has gone.
    KernelCountersReading read();

    const std::string& interface() const { return interface_; }

  private:
    std::string interface_;
    NlSocketPtr socket_;
};

}  // namespace tgw::sensor
