#include "sensor/netlink_handles.hpp"

#include <netlink/netlink.h>
#include <netlink/route/link.h>
#include <netlink/route/qdisc.h>

#include <string>

#include "base/config_error.hpp"

namespace tgw::sensor {

void NlSocketFree::operator()(nl_sock* socket) const {
    nl_socket_free(socket);
}

void NlCacheFree::operator()(nl_cache* cache) const {
    nl_cache_free(cache);
}

void RtnlLinkPut::operator()(rtnl_link* link) const {
    rtnl_link_put(link);
}

void RtnlQdiscPut::operator()(rtnl_qdisc* qdisc) const {
    rtnl_qdisc_put(qdisc);
}

NlSocketPtr connect_rtnetlink() {
    NlSocketPtr socket(nl_socket_alloc());
    if (!socket)
        throw base::ConfigError("cannot allocate a netlink socket");
    if (const int err = nl_connect(socket.get(), NETLINK_ROUTE); err < 0)
        throw base::ConfigError(std::string("cannot open rtnetlink: ") + nl_geterror(err));
    return socket;
}

}  // namespace tgw::sensor
