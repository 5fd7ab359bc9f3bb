// The --wan-peer host names looked up again while the gateway runs: a camp laptop on DHCP, a name that resolves
// late.
#pragma once

#include <chrono>
#include <condition_variable>
#include <functional>
#include <mutex>
#include <thread>
#include <vector>

#include "gateway/dds/wan_address.hpp"

namespace tgw::dds {

/// Looks the peers' host names up every PERIOD in a thread of its own and tells `changed` the peers with their
/// new addresses when one moved. A resolver that fails for a while changes nothing: the last address stays.
class PeerLookup {
  public:
    using Changed = std::function<void(const std::vector<WanPeer>& peers)>;
    static constexpr std::chrono::seconds PERIOD{5};

    /// `peers` as resolved at start; starts the thread.
    PeerLookup(std::vector<WanPeer> peers, Changed changed);
    /// Stops.
    ~PeerLookup();
    PeerLookup(const PeerLookup&) = delete;
    PeerLookup& operator=(const PeerLookup&) = delete;

    /// Ends the thread, a lookup under way first. Idempotent.
    void stop();

  private:
    void run();

    const std::vector<WanPeer> given_;
    Changed changed_;
    std::mutex mutex_;
    std::condition_variable wake_;
    bool stopping_ = false;  // under mutex_
    std::thread thread_;
};

}  // namespace tgw::dds
