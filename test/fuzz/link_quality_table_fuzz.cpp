// wireless:IFACE:table=FILE comes from an operator's file: any text gives a valid table or a ConfigError naming
// the file.
#include <cmath>
#include <sstream>

#include "base/config_error.hpp"
#include "sensor/link_quality_table.hpp"
#include "test/fuzz/fuzz_target.hpp"

namespace tgw::fuzz {

std::vector<std::string> seeds() {
    return {
        "# quality rate\n0 500k\n10 1M\n20 2.5M\n30 5M\n40 12M\n50 18M\n60 25M\n",
        "5 10000\r\n\n7.5 20000 # comment\n",
        "0 0\n",
    };
}

}  // namespace tgw::fuzz

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    using namespace tgw;
    std::istringstream in(std::string(reinterpret_cast<const char*>(data), size));
    try {
        const sensor::LinkQualityTable table = sensor::parse_link_quality_table(in, "fuzz.table");
        const auto& rows = table.rows();
        TGW_FUZZ_CHECK(!rows.empty());
        for (std::size_t i = 0; i < rows.size(); ++i) {
            TGW_FUZZ_CHECK(std::isfinite(rows[i].rate_bps) && rows[i].rate_bps >= 0.0);
            TGW_FUZZ_CHECK(std::isfinite(rows[i].min_quality));
            TGW_FUZZ_CHECK(i == 0 || rows[i - 1].min_quality < rows[i].min_quality);
            TGW_FUZZ_CHECK(table.rate_for(rows[i].min_quality) == rows[i].rate_bps);
        }
        TGW_FUZZ_CHECK(!table.rate_for(std::nextafter(rows.front().min_quality, -INFINITY)));
    } catch (const base::ConfigError& e) {
        TGW_FUZZ_CHECK(std::string(e.what()).rfind("fuzz.table", 0) == 0);
    }
    return 0;
}
