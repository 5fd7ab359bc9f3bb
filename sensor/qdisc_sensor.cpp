#include "sensor/qdisc_sensor.hpp"

#include <linux/pkt_sched.h>
#include <netlink/netlink.h>
#include <netlink/route/class.h>
#include <netlink/route/link.h>
#include <netlink/route/qdisc.h>
#include <netlink/route/qdisc/htb.h>
#include <netlink/route/qdisc/tbf.h>
#include <netlink/route/tc.h>

#include <cstdint>
#include <utility>

#include "base/config_error.hpp"
#include "sensor/netlink_handles.hpp"

namespace tgw::sensor {

namespace {

RateReading success(double rate_bps, std::string detail) {
    RateReading reading;
    reading.ok = true;
    reading.rate_bps = rate_bps;
    reading.detail = std::move(detail);
    return reading;
}

std::string handle_text(std::uint32_t handle) {
    char buffer[32];
    rtnl_tc_handle2str(handle, buffer, sizeof buffer);
    return buffer;
}

/// htb shapes in its classes: the link's rate is what its top-level classes may send together.
RateReading read_htb(nl_sock* socket, const std::string& interface, int ifindex, std::uint32_t qdisc_handle) {
    nl_cache* raw = nullptr;
    if (const int err = rtnl_class_alloc_cache(socket, ifindex, &raw); err < 0)
        return failed_reading("cannot list the htb classes of " + interface + ": " + nl_geterror(err));
    NlCachePtr classes(raw);
    std::uint64_t total_bytes_per_s = 0;
    std::string roots;
    for (nl_object* object = nl_cache_get_first(classes.get()); object != nullptr; object = nl_cache_get_next(object)) {
        auto* cls = reinterpret_cast<rtnl_class*>(object);
        const std::uint32_t parent = rtnl_tc_get_parent(TC_CAST(cls));
        // The kernel reports a top-level class's parent as the root; older kernels as the qdisc's handle.
        if (parent != TC_H_ROOT && parent != qdisc_handle)
            continue;
        std::uint64_t rate = 0;
        if (rtnl_htb_get_rate64(cls, &rate) < 0)
            continue;
        total_bytes_per_s += rate;
        roots += (roots.empty() ? "" : ",") + handle_text(rtnl_tc_get_handle(TC_CAST(cls)));
    }
    if (roots.empty())
        return failed_reading("htb at the root of " + interface + " has no top-level class with a rate");
    return success(8.0 * static_cast<double>(total_bytes_per_s), "htb class " + roots);
}

/// Whether `interface` exists in the network namespace of `socket`.
bool has_link(nl_sock* socket, const std::string& interface) {
    rtnl_link* raw_link = nullptr;
    if (rtnl_link_get_kernel(socket, 0, interface.c_str(), &raw_link) < 0)
        return false;
    const RtnlLinkPtr link(raw_link);
    return true;
}

/// One reading of the root shaper of `interface`, in the network namespace of `socket`.
RateReading read_root_shaper(nl_sock* socket, const std::string& interface) {
    rtnl_link* raw_link = nullptr;
    if (const int err = rtnl_link_get_kernel(socket, 0, interface.c_str(), &raw_link); err < 0)
        return failed_reading("no interface " + interface + ": " + nl_geterror(err));
    const int ifindex = rtnl_link_get_ifindex(RtnlLinkPtr(raw_link).get());

    nl_cache* raw_cache = nullptr;
    if (const int err = rtnl_qdisc_alloc_cache(socket, &raw_cache); err < 0)
        return failed_reading("cannot list the qdiscs of " + interface + ": " + nl_geterror(err));
    NlCachePtr qdiscs(raw_cache);
    RtnlQdiscPtr root(rtnl_qdisc_get_by_parent(qdiscs.get(), ifindex, TC_H_ROOT));
    if (!root)
        return failed_reading(interface + " has no root qdisc, so no shaper");
    const char* kind = rtnl_tc_get_kind(TC_CAST(root.get()));
    const std::string kind_name = kind ? kind : "";
    RateReading reading;
    if (kind_name == "tbf") {
        const int bytes_per_s = rtnl_qdisc_tbf_get_rate(root.get());
        if (bytes_per_s < 0)
            return failed_reading("tbf at the root of " + interface + " reports no rate");
        reading = success(8.0 * bytes_per_s, "tbf");
    } else if (kind_name == "htb") {
        reading = read_htb(socket, interface, ifindex, rtnl_tc_get_handle(TC_CAST(root.get())));
    } else {
        return failed_reading("the root qdisc of " + interface + " is " + (kind_name.empty() ? "unnamed" : kind_name) +
                              ", not a shaper this sensor reads (tbf, htb)");
    }
    if (reading.ok) {
        reading.queued_bytes = rtnl_tc_get_stat(TC_CAST(root.get()), RTNL_TC_BACKLOG);
        reading.detail += ", backlog " + std::to_string(*reading.queued_bytes) + " B";
    }
    return reading;
}

}  // namespace

QdiscSensor::QdiscSensor(std::string interface) : interface_(std::move(interface)) {
    if (interface_.empty())
        throw base::ConfigError("no interface given (qdisc:IFACE)");
    socket_ = connect_rtnetlink();
    // A radio's interface may appear after the gateway starts (a USB modem, a driver loaded late): until then its
    // readings fail, as they do when it goes. One that is there must have a shaper this sensor reads.
    const RateReading first = read();
    if (!first.ok && has_link(socket_.get(), interface_))
        throw base::ConfigError(first.error);
}

QdiscSensor::~QdiscSensor() = default;

RateReading QdiscSensor::read() {
    try {
        return read_root_shaper(socket_.get(), interface_);
    } catch (const std::exception& e) {  // allocation only; never let a poll throw
        return failed_reading(e.what());
    }
}

std::string QdiscSensor::describe() const {
    return "qdisc:" + interface_;
}

}  // namespace tgw::sensor
