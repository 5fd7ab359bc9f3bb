#pragma once

#include <memory>

struct nl_cache;
struct nl_sock;
struct rtnl_link;
struct rtnl_qdisc;

namespace tgw::sensor {

// Owning handles for the rtnetlink objects the netlink sensors share, so that every early return frees them. Declared
// without libnl's headers so that a sensor's public header can hold a socket; netlink_handles.cpp frees them.

struct NlSocketFree {
    void operator()(nl_sock* socket) const;  ///< closes it too
};
struct NlCacheFree {
    void operator()(nl_cache* cache) const;
};
struct RtnlLinkPut {
    void operator()(rtnl_link* link) const;
};
struct RtnlQdiscPut {
    void operator()(rtnl_qdisc* qdisc) const;
};

using NlSocketPtr = std::unique_ptr<nl_sock, NlSocketFree>;
using NlCachePtr = std::unique_ptr<nl_cache, NlCacheFree>;
using RtnlLinkPtr = std::unique_ptr<rtnl_link, RtnlLinkPut>;
using RtnlQdiscPtr = std::unique_ptr<rtnl_qdisc, RtnlQdiscPut>;

/// A socket connected to rtnetlink, in the network namespace of the calling thread. Throws base::ConfigError
/// saying which step failed.
NlSocketPtr connect_rtnetlink();

}  // namespace tgw::sensor
