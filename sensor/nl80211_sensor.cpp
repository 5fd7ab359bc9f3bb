#include "sensor/nl80211_sensor.hpp"

#include <linux/nl80211.h>
#include <net/if.h>
#include <netlink/genl/ctrl.h>
#include <netlink/genl/genl.h>
#include <netlink/msg.h>
#include <netlink/netlink.h>
#include <sys/socket.h>
#include <sys/time.h>

#include <utility>
#include <vector>

#include "base/config_error.hpp"
#include "sensor/netlink_handles.hpp"

namespace tgw::sensor {

namespace {

/// A poll must not hang the gateway on a wedged driver.
constexpr long REPLY_TIMEOUT_S = 1;

struct MsgFree {
    void operator()(nl_msg* message) const { nlmsg_free(message); }
};
struct CbPut {
    void operator()(nl_cb* cb) const { nl_cb_put(cb); }
};

/// nl80211 answers a station dump on a netdev without a wireless device with ENODEV (or EOPNOTSUPP).
bool means_not_wireless(int nl_error) {
    return nl_error == -NLE_OBJ_NOTFOUND || nl_error == -NLE_NODEV || nl_error == -NLE_OPNOTSUPP;
}

}  // namespace

struct Nl80211Sensor::Dump {
    std::vector<StationInfo> stations;
    std::string parse_error;  ///< the first station message that did not parse
    bool finished = false;    ///< NLMSG_DONE seen
    int nl_error = 0;         ///< from libnl or the kernel, < 0 on failure
};

Nl80211Sensor::Nl80211Sensor(std::string interface, std::optional<MacAddress> peer)
    : interface_(std::move(interface)), peer_(peer) {
    if (interface_.empty())
        throw base::ConfigError("no interface given (nl80211:IFACE[:PEER_MAC])");
    // A radio's interface may appear after the gateway starts (a USB dongle, its driver loaded with it): until then
    // its readings fail, as they do when it goes. One that is there must be wireless.
    const unsigned ifindex = if_nametoindex(interface_.c_str());
    if (ifindex == 0)
        return;
    if (auto error = connect(); !error.empty())
        throw base::ConfigError(error);
    const Dump dump = dump_stations(static_cast<int>(ifindex));
    if (means_not_wireless(dump.nl_error))
        throw base::ConfigError(interface_ + " is not a wireless interface: nl80211 does not know it (" +
                                nl_geterror(dump.nl_error) + ")");
    if (dump.nl_error < 0)
        throw base::ConfigError("cannot list the stations of " + interface_ + ": " + nl_geterror(dump.nl_error));
}

Nl80211Sensor::~Nl80211Sensor() = default;

std::string Nl80211Sensor::connect() {
    socket_.reset(nl_socket_alloc());
    if (!socket_)
        return "cannot allocate a netlink socket";
    if (const int err = genl_connect(socket_.get()); err < 0)
        return std::string("cannot open generic netlink: ") + nl_geterror(err);
    family_ = genl_ctrl_resolve(socket_.get(), "nl80211");
    if (family_ < 0)
        return interface_ + " is not a wireless interface: the kernel has no nl80211 (no wireless driver loaded)";
    const timeval timeout{REPLY_TIMEOUT_S, 0};
    setsockopt(nl_socket_get_fd(socket_.get()), SOL_SOCKET, SO_RCVTIMEO, &timeout, sizeof timeout);
    return {};
}

Nl80211Sensor::Dump Nl80211Sensor::dump_stations(int ifindex) {
    Dump dump;
    std::unique_ptr<nl_msg, MsgFree> request(nlmsg_alloc());
    std::unique_ptr<nl_cb, CbPut> cb(nl_cb_alloc(NL_CB_DEFAULT));
    if (!request || !cb) {
        dump.nl_error = -NLE_NOMEM;
        return dump;
    }
    if (genlmsg_put(request.get(), NL_AUTO_PORT, NL_AUTO_SEQ, family_, 0, NLM_F_DUMP, NL80211_CMD_GET_STATION, 0) ==
            nullptr ||
        nla_put_u32(request.get(), NL80211_ATTR_IFINDEX, static_cast<std::uint32_t>(ifindex)) < 0) {
        dump.nl_error = -NLE_NOMEM;
        return dump;
    }
    nl_cb_set(
        cb.get(), NL_CB_VALID, NL_CB_CUSTOM,
        [](nl_msg* message, void* arg) {
            auto* state = static_cast<Dump*>(arg);
            StationParseResult parsed = parse_station_message(message);
            if (parsed.ok)
                state->stations.push_back(parsed.station);
            else if (state->parse_error.empty())
                state->parse_error = std::move(parsed.error);
            return static_cast<int>(NL_OK);
        },
        &dump);
    nl_cb_set(
        cb.get(), NL_CB_FINISH, NL_CB_CUSTOM,
        [](nl_msg*, void* arg) {
            static_cast<Dump*>(arg)->finished = true;
            return static_cast<int>(NL_STOP);
        },
        &dump);
    if (const int err = nl_send_auto(socket_.get(), request.get()); err < 0) {
        dump.nl_error = err;
        return dump;
    }
    while (!dump.finished) {
        const int err = nl_recvmsgs(socket_.get(), cb.get());
        if (err < 0) {
            dump.nl_error = err;
            break;
        }
        if (err == 0 && !dump.finished) {  // libnl returns 0 when the receive timed out
            dump.nl_error = -NLE_AGAIN;
            break;
        }
    }
    return dump;
}

RateReading Nl80211Sensor::read() {
    try {
        const unsigned ifindex = if_nametoindex(interface_.c_str());
        if (ifindex == 0)
            return failed_reading("no interface " + interface_);
        if (!socket_) {
            if (auto error = connect(); !error.empty()) {
                socket_.reset();
                return failed_reading(error);
            }
        }
        const Dump dump = dump_stations(static_cast<int>(ifindex));
        if (dump.nl_error < 0) {
            // A reply may still be on its way and would confuse the next dump: start afresh next time.
            socket_.reset();
            if (means_not_wireless(dump.nl_error))
                return failed_reading(interface_ + " is not a wireless interface now (" + nl_geterror(dump.nl_error) +
                                      ")");
            return failed_reading("cannot list the stations of " + interface_ + ": " + nl_geterror(dump.nl_error));
        }
        if (!dump.parse_error.empty())
            return failed_reading("bad station message from nl80211 on " + interface_ + ": " + dump.parse_error);
        return station_reading(dump.stations, peer_, interface_);
    } catch (const std::exception& e) {  // allocation only; never let a poll throw
        return failed_reading(e.what());
    }
}

std::string Nl80211Sensor::describe() const {
    return "nl80211:" + interface_ + (peer_ ? ":" + mac_text(*peer_) : "");
}

}  // namespace tgw::sensor
