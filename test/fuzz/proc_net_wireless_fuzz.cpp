// /proc/net/wireless is read on every poll: any text gives interfaces or an error, and never throws.
#include <cmath>
#include <sstream>

#include "sensor/proc_net_wireless.hpp"
#include "test/fuzz/fuzz_target.hpp"

namespace tgw::fuzz {

std::vector<std::string> seeds() {
    return {
        "Inter-| sta-|   Quality        |   Discarded packets               | Missed | WE\n"
        " face | tus | link level noise |  nwid  crypt   frag  retry   misc | beacon | 22\n"
        " wlan0: 0000   54.  -56.  -256        0      0      0      0      0        0\n",
        "Inter-| sta-|   Quality        |   Discarded packets               | Missed | WE\n"
        " face | tus | link level noise |  nwid  crypt   frag  retry   misc | beacon | 22\n"
        " wlan0: 0000   54.  -56.  -256        0      0      0      0      0        0\n"
        "wlp2s0: 0000   70   -40   -95         1      2      3      4      5        6\n",
        "",
    };
}

}  // namespace tgw::fuzz

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    using namespace tgw;
    std::istringstream in(std::string(reinterpret_cast<const char*>(data), size));
    const sensor::WirelessTable table = sensor::parse_proc_net_wireless(in);
    if (!table.ok) {
        TGW_FUZZ_CHECK(!table.error.empty());
        return 0;
    }
    for (const sensor::WirelessStatus& status : table.interfaces) {
        TGW_FUZZ_CHECK(!status.interface.empty());
        TGW_FUZZ_CHECK(std::isfinite(status.link_quality));
    }
    return 0;
}
