// The --wan-peer host names looked up again while the gateway runs: a camp laptop on DHCP, a name that resolves
// late.
#pragma once

#include <chrono>
#include <functional>
#include <vector>

#include "base/event_loop.hpp"
#include "base/wan_address.hpp"

namespace tgw::dds {

/// Looks the peers' host names up every PERIOD in a thread of its own (a base::EventLoop) and tells `changed` the peers
/// with their new addresses when one moved. A resolver that fails for a while changes nothing: the last address stays.
class PeerLookup {
  public:
    using Changed = std::function<void(const std::vector<base::WanPeer>& peers)>;
    static constexpr std::chrono::seconds PERIOD{5};

    /// `peers` as resolved at start; starts the thread, whose first lookup is PERIOD away.
    PeerLookup(std::vector<base::WanPeer> peers, Changed changed);
    /// Stops.
    ~PeerLookup();
    PeerLookup(const PeerLookup&) = delete;
    PeerLookup& operator=(const PeerLookup&) = delete;

    /// Ends the thread, a lookup under way first. Idempotent.
    void stop();

  private:
    void look();

    const std::vector<base::WanPeer> given_;
    const Changed changed_;
    std::vector<base::WanPeer> known_;  // in the loop's thread only
    base::EventLoop loop_;
};

}  // namespace tgw::dds
