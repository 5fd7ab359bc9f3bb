#include "sensor/link_state_watch.hpp"

#include <net/if.h>
#include <netlink/netlink.h>
#include <netlink/route/link.h>
#include <poll.h>
#include <sys/eventfd.h>
#include <unistd.h>

#include <cstdint>
#include <utility>

#include "base/config_error.hpp"
#include "base/interface_addresses.hpp"

namespace tgw::sensor {

const char* describe(const LinkState& state) {
    if (!state.exists)
        return "absent";
    if (!state.up)
        return "down";
    return state.addresses.empty() ? "up without an IPv4 address" : "up";
}

LinkStateWatch::LinkStateWatch(std::string interface, std::function<void(const LinkState&)> on_change,
                               std::chrono::milliseconds recheck)
    : interface_(std::move(interface)),
      on_change_(std::move(on_change)),
      recheck_(recheck),
      events_(connect_rtnetlink()),
      queries_(connect_rtnetlink()) {
    // Notifications carry no sequence numbers of ours; their content is not needed, only that something changed.
    nl_socket_disable_seq_check(events_.get());
    if (const int err = nl_socket_add_memberships(events_.get(), RTNLGRP_LINK, RTNLGRP_IPV4_IFADDR, 0); err < 0)
        throw base::ConfigError(std::string("cannot follow the links' state through rtnetlink: ") + nl_geterror(err));
    nl_socket_set_nonblocking(events_.get());
    stop_fd_ = eventfd(0, EFD_CLOEXEC | EFD_NONBLOCK);
    if (stop_fd_ < 0)
        throw base::ConfigError("cannot make an eventfd to stop the link-state watch");
}

LinkStateWatch::~LinkStateWatch() {
    stop();
    close(stop_fd_);
}

void LinkStateWatch::start() {
    const LinkState first = read_state();
    {
        std::lock_guard<std::mutex> lock(mutex_);
        state_ = first;
    }
    if (on_change_)
        on_change_(first);
    thread_ = std::thread([this] { run(); });
}

void LinkStateWatch::stop() {
    if (!thread_.joinable())
        return;
    const std::uint64_t one = 1;
    [[maybe_unused]] const ssize_t written = write(stop_fd_, &one, sizeof one);
    thread_.join();
}

LinkState LinkStateWatch::state() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return state_;
}

LinkState LinkStateWatch::read_state() {
    rtnl_link* raw_link = nullptr;
    if (rtnl_link_get_kernel(queries_.get(), 0, interface_.c_str(), &raw_link) < 0)
        return LinkState{};
    const RtnlLinkPtr link(raw_link);
    const unsigned int flags = rtnl_link_get_flags(link.get());
    LinkState state{true, (flags & IFF_UP) != 0 && (flags & IFF_RUNNING) != 0, {}};
    if (const auto addresses = base::interface_addresses()) {
        for (const base::InterfaceAddress& each : *addresses) {
            if (each.interface == interface_)
                state.addresses.push_back(each.address);
        }
    }
    return state;
}

void LinkStateWatch::run() {
    pollfd fds[2] = {{nl_socket_get_fd(events_.get()), POLLIN, 0}, {stop_fd_, POLLIN, 0}};
    for (;;) {
        const int ready = poll(fds, 2, static_cast<int>(recheck_.count()));
        if (ready > 0 && (fds[1].revents & POLLIN) != 0)
            return;
        if (ready > 0 && (fds[0].revents & POLLIN) != 0) {
            // Drains what came (several links may have changed); which link it was is asked below.
            while (nl_recvmsgs_default(events_.get()) >= 0) {
            }
        }
        const LinkState now = read_state();
        if (now != state()) {
            {
                std::lock_guard<std::mutex> lock(mutex_);
                state_ = now;
            }
            if (on_change_)
                on_change_(now);
        }
    }
}

}  // namespace tgw::sensor
