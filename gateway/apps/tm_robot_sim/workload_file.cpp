#include "gateway/apps/tm_robot_sim/workload_file.hpp"

#include <fstream>
#include <sstream>

#include "base/config_error.hpp"

namespace tgw::robot_sim {

std::vector<core::MessageStream> parse_workload(std::istream& in, const std::string& name, double default_rate_hz) {
    std::vector<core::MessageStream> streams;
    std::string line;
    for (int number = 1; std::getline(in, line); ++number) {
        const auto hash = line.find('#');
        if (hash != std::string::npos)
            line.erase(hash);
        std::istringstream fields(line);
        core::MessageStream stream;
        double ttl_s = 0.0;
        long long bytes = -1;
        if (!(fields >> stream.type))
            continue;  // blank or comment
        const auto where = name + ":" + std::to_string(number) + ": ";
        if (!(fields >> stream.topic >> bytes >> ttl_s))
            throw base::ConfigError(where + "expected 'TYPE TOPIC DATA_BYTES TTL_S [RATE_HZ]'");
        if (bytes < 0)
            throw base::ConfigError(where + "DATA_BYTES must be zero or more");
        if (ttl_s <= 0.0)
            throw base::ConfigError(where + "TTL_S must be positive");
        stream.data_bytes = static_cast<std::size_t>(bytes);
        stream.ttl = base::from_seconds(ttl_s);
        stream.rate_hz = default_rate_hz;
        if (fields >> stream.rate_hz) {
            if (stream.rate_hz <= 0.0)
                throw base::ConfigError(where + "RATE_HZ must be positive");
        } else if (!fields.eof()) {
            throw base::ConfigError(where + "RATE_HZ is not a number");
        }
        std::string extra;
        if (fields.clear(), fields >> extra)
            throw base::ConfigError(where + "unexpected '" + extra + "'");
        streams.push_back(stream);
    }
    if (streams.empty())
        throw base::ConfigError(name + ": no streams");
    return streams;
}

std::vector<core::MessageStream> load_workload(const std::string& spec, double rate_hz) {
    if (spec == "paper")
        return core::paper_workload(rate_hz);
    std::ifstream file(spec);
    if (!file)
        throw base::ConfigError("--workload: cannot open '" + spec + "'");
    return parse_workload(file, spec, rate_hz);
}

}  // namespace tgw::robot_sim
