// trace:FILE comes from an operator's file: any text gives a valid trace or a ConfigError naming the file.
#include <cmath>
#include <sstream>

#include "base/config_error.hpp"
#include "sensor/rate_trace.hpp"
#include "test/fuzz/fuzz_target.hpp"

namespace tgw::fuzz {

std::vector<std::string> seeds() {
    return {
        "0 50000\n20 10000\n30 1000\n40 30000\n",
        "# the paper's future work 7.4\n\n0 50k\r\n20.5 1.5M   # tail comment\n60 0\n",
        "5 70000",
        "0 10000\n0 20000\n",
    };
}

}  // namespace tgw::fuzz

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    using namespace tgw;
    std::istringstream in(std::string(reinterpret_cast<const char*>(data), size));
    try {
        const sensor::RateTrace trace = sensor::parse_rate_trace(in, "fuzz.trace");
        const auto& steps = trace.steps();
        TGW_FUZZ_CHECK(!steps.empty());
        for (std::size_t i = 0; i < steps.size(); ++i) {
            TGW_FUZZ_CHECK(std::isfinite(steps[i].rate_bps) && steps[i].rate_bps >= 0.0);
            TGW_FUZZ_CHECK(steps[i].at >= base::Duration::zero());
            TGW_FUZZ_CHECK(i == 0 || steps[i - 1].at < steps[i].at);
            TGW_FUZZ_CHECK(trace.rate_at(steps[i].at) == steps[i].rate_bps);
        }
        TGW_FUZZ_CHECK(trace.rate_at(base::Duration::zero()) == steps.front().rate_bps);
        TGW_FUZZ_CHECK(trace.rate_at(steps.back().at + std::chrono::hours(1)) == steps.back().rate_bps);
    } catch (const base::ConfigError& e) {
        TGW_FUZZ_CHECK(std::string(e.what()).rfind("fuzz.trace", 0) == 0);
    }
    return 0;
}
