// Whether the radio's interface can carry anything now, from the kernel's own word (rtnetlink).
#pragma once

#include <atomic>
#include <chrono>
#include <functional>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "sensor/netlink_handles.hpp"

namespace tgw::sensor {

/// An interface's state as the kernel sees it.
struct LinkState {
    bool exists = false;
    /// Administratively up (IFF_UP) and running (IFF_RUNNING: carrier, a radio associated, the veth's peer up).
    bool up = false;
    /// Its IPv4 addresses, in the kernel's order; none while it has none. A DHCP lease or a mesh radio may change
    /// them.
    std::vector<std::string> addresses;

    bool operator==(const LinkState& other) const {
        return exists == other.exists && up == other.up && addresses == other.addresses;
    }
    bool operator!=(const LinkState& other) const { return !(*this == other); }
    /// What IPv4 can be sent through it now: up, with an address.
    bool usable() const { return up && !addresses.empty(); }
};

/// "up", "down", "up without an IPv4 address" or "absent", for messages.
const char* describe(const LinkState& state);

/// Follows an interface's state through rtnetlink's link and address notifications (RTNLGRP_LINK,
/// RTNLGRP_IPV4_IFADDR), in a thread of its own,
/// and calls `on_change` with each new state: a radio that goes down, is not up yet at start, or is unplugged
/// (an interface that does not exist yet is a state too, not an error). The kernel tells at once; it also looks
/// again every `recheck`, should a notification be lost. Watches the network namespace of the thread that built
/// it.
class LinkStateWatch {
  public:
    /// Throws base::ConfigError when rtnetlink cannot be opened.
    LinkStateWatch(std::string interface, std::function<void(const LinkState&)> on_change,
                   std::chrono::milliseconds recheck = std::chrono::seconds(1));
    ~LinkStateWatch();

    LinkStateWatch(const LinkStateWatch&) = delete;
    LinkStateWatch& operator=(const LinkStateWatch&) = delete;

    /// Reads the state once in the calling thread and hands it to `on_change` (so the gateway starts from the
    /// truth), then starts following it.
    void start();
    void stop();

    LinkState state() const;
    const std::string& interface() const { return interface_; }

  private:
    LinkState read_state();
    void run();

    const std::string interface_;
    const std::function<void(const LinkState&)> on_change_;
    const std::chrono::milliseconds recheck_;
    NlSocketPtr events_;   // subscribed to link notifications
    NlSocketPtr queries_;  // asks for the interface
    int stop_fd_ = -1;     // an eventfd that wakes the thread to stop
    mutable std::mutex mutex_;
    LinkState state_;  // under mutex_
    std::thread thread_;
};

}  // namespace tgw::sensor
