#include "gateway/dds/peer_lookup.hpp"

#include <iostream>
#include <utility>

namespace tgw::dds {

PeerLookup::PeerLookup(std::vector<base::WanPeer> peers, Changed changed)
    : given_(std::move(peers)), changed_(std::move(changed)), known_(given_) {
    loop_.start();
    loop_.post_every(PERIOD, [this] { look(); });
}

PeerLookup::~PeerLookup() {
    stop();
}

void PeerLookup::stop() {
    loop_.stop();
}

void PeerLookup::look() {
    std::vector<base::WanPeer> now = base::resolve_peer_names(given_);  // the resolver may take seconds
    for (std::size_t i = 0; i < now.size(); ++i) {
        if (now[i].address.empty()) {
            now[i].address = known_[i].address;  // a resolver that fails for a while changes nothing
        }
    }
    if (now == known_) {
        return;
    }
    for (std::size_t i = 0; i < now.size(); ++i) {
        if (now[i] != known_[i]) {
            std::cerr << "telemetry-gateway: --wan-peer " << now[i].host << " is " << now[i].address
                      << " now: the WAN participant is made anew to announce to it\n";
        }
    }
    known_ = now;
    changed_(now);
}

}  // namespace tgw::dds
