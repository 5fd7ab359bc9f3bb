#include "sensor/link_counter_reader.hpp"

#include <linux/pkt_sched.h>
#include <netlink/netlink.h>
#include <netlink/route/link.h>
#include <netlink/route/qdisc.h>
#include <netlink/route/tc.h>

#include <utility>

#include "base/config_error.hpp"
#include "sensor/netlink_handles.hpp"

namespace tgw::sensor {

namespace {

KernelCountersReading failure(std::string error) {
    KernelCountersReading reading;
    reading.error = std::move(error);
    return reading;
}

}  // namespace

LinkCounterReader::LinkCounterReader(std::string interface) : interface_(std::move(interface)) {
    if (interface_.empty())
        throw base::ConfigError("no interface given for the delivered-rate check");
    socket_ = connect_rtnetlink();
    if (const KernelCountersReading first = read(); !first.ok)
        throw base::ConfigError(first.error);
}

LinkCounterReader::~LinkCounterReader() = default;

KernelCountersReading LinkCounterReader::read() {
    try {
        rtnl_link* raw_link = nullptr;
        if (const int err = rtnl_link_get_kernel(socket_.get(), 0, interface_.c_str(), &raw_link); err < 0)
            return failure("no interface " + interface_ + ": " + nl_geterror(err));
        const RtnlLinkPtr link(raw_link);
        KernelCountersReading reading;
        reading.counters.tx_bytes = rtnl_link_get_stat(link.get(), RTNL_LINK_TX_BYTES);
        const int ifindex = rtnl_link_get_ifindex(link.get());

        nl_cache* raw_cache = nullptr;
        if (const int err = rtnl_qdisc_alloc_cache(socket_.get(), &raw_cache); err < 0)
            return failure("cannot list the qdiscs of " + interface_ + ": " + nl_geterror(err));
        const NlCachePtr qdiscs(raw_cache);
        // No root qdisc (noqueue): nothing can queue or drop before the driver.
        if (const RtnlQdiscPtr root(rtnl_qdisc_get_by_parent(qdiscs.get(), ifindex, TC_H_ROOT)); root) {
            reading.counters.drops = rtnl_tc_get_stat(TC_CAST(root.get()), RTNL_TC_DROPS);
            reading.counters.backlog_bytes = rtnl_tc_get_stat(TC_CAST(root.get()), RTNL_TC_BACKLOG);
        }
        reading.ok = true;
        return reading;
    } catch (const std::exception& e) {  // allocation only; never let a poll throw
        return failure(e.what());
    }
}

}  // namespace tgw::sensor
