#include "sensor/netlink_handles.hpp"

#include <netlink/netlink.h>
#include <netlink/route/link.h>
#include <netlink/route/qdisc.h>

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

}  // namespace tgw::sensor
