#include "gateway/dds/peer_lookup.hpp"

#include <iostream>
#include <utility>

namespace tgw::dds {

PeerLookup::PeerLookup(std::vector<WanPeer> peers, Changed changed)
    : given_(std::move(peers)), changed_(std::move(changed)), thread_([this] { run(); }) {}

PeerLookup::~PeerLookup() {
    stop();
}

void PeerLookup::stop() {
    {
        std::lock_guard<std::mutex> lock(mutex_);
        stopping_ = true;
    }
    wake_.notify_all();
    if (thread_.joinable()) {
        thread_.join();
    }
}

void PeerLookup::run() {
    std::vector<WanPeer> known = given_;
    std::unique_lock<std::mutex> lock(mutex_);
    while (!wake_.wait_for(lock, PERIOD, [this] { return stopping_; })) {
        lock.unlock();
        std::vector<WanPeer> now = resolve_peer_names(given_);  // the resolver may take seconds
        lock.lock();
        for (std::size_t i = 0; i < now.size(); ++i) {
            if (now[i].address.empty()) {
                now[i].address = known[i].address;  // a resolver that fails for a while changes nothing
            }
        }
        if (now == known) {
            continue;
        }
        for (std::size_t i = 0; i < now.size(); ++i) {
            if (now[i] != known[i]) {
                std::cerr << "telemetry-gateway: --wan-peer " << now[i].host << " is " << now[i].address
                          << " now: the WAN participant is made anew to announce to it\n";
            }
        }
        known = now;
        changed_(now);
    }
}

}  // namespace tgw::dds
