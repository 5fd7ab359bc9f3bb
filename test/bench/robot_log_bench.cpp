// How many samples per second the on-robot log absorbs during an outage, when everything the robot publishes
// goes to it: rows appended as fast as one thread can (the gateway's drop path), timed until they are all
// committed to a real SQLite file. rows/s counts the rows committed; `lost` the rows refused because the log's
// buffer was full (the disk not keeping up). Also the cost of append() itself, which the forwarding path pays.
#include <CLI/CLI.hpp>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

#include "base/cli_checks.hpp"
#include "gateway/log/robot_log.hpp"

namespace {

using Clock = std::chrono::steady_clock;
namespace fs = std::filesystem;

struct Result {
    double rows_per_s = 0.0;
    double mib_per_s = 0.0;
    double append_median_us = 0.0;
    double append_p99_us = 0.0;
    std::uint64_t errors = 0;
    double file_mib = 0.0;
};

double percentile(std::vector<double>& values, double p) {
    const auto at = static_cast<std::size_t>(p * static_cast<double>(values.size() - 1));
    std::nth_element(values.begin(), values.begin() + static_cast<std::ptrdiff_t>(at), values.end());
    return values[at];
}

Result absorb(const fs::path& file, std::size_t payload_bytes, std::size_t rows) {
    tgw::core::Sample sample;
    sample.topic = 3;
    sample.payload.assign(payload_bytes, 0xa5);
    sample.key.valid = true;
    sample.source_time = tgw::base::WallClock::now();
    std::vector<double> append_us;
    append_us.reserve(rows);

    Result result;
    const auto start = Clock::now();
    {
        tgw::log::RobotLog log(file.string());
        for (std::size_t i = 0; i < rows; ++i) {
            sample.sequence = i;
            tgw::log::LogRecord record;
            record.topic = "telemetry/D";
            record.type_name = "tgw::idl::PaperMessage";
            record.sample = &sample;
            record.reason = tgw::core::DropReason::expired;
            record.arrival = record.deadline = record.logged_at = sample.source_time;
            const auto before = Clock::now();
            log.append(record);
            append_us.push_back(std::chrono::duration<double, std::micro>(Clock::now() - before).count());
        }
        log.flush();
        result.errors = log.write_errors();
    }
    const double seconds = std::chrono::duration<double>(Clock::now() - start).count();
    // What reached the file: past the log's 256 MiB buffer a burst faster than the disk loses rows (counted).
    result.rows_per_s = static_cast<double>(rows - result.errors) / seconds;
    result.mib_per_s = result.rows_per_s * static_cast<double>(payload_bytes) / (1 << 20);
    result.append_median_us = percentile(append_us, 0.5);
    result.append_p99_us = percentile(append_us, 0.99);
    result.file_mib = static_cast<double>(fs::file_size(file)) / (1 << 20);
    return result;
}

}  // namespace

int main(int argc, char** argv) {
    CLI::App app{"robot_log_bench: samples per second the on-robot SQLite log absorbs during an outage"};
    std::vector<std::size_t> sizes{41, 1016, 4096, 65536};
    std::size_t rows = 200'000;
    std::string dir = fs::temp_directory_path().string();
    app.add_option("--size", sizes, "payload bytes per row; repeatable")->capture_default_str();
    app.add_option("--rows", rows, "rows per size (fewer for payloads over 4 KiB: at most 1 GiB each)")
        ->check(tgw::base::positive())
        ->capture_default_str();
    app.add_option("--dir", dir, "directory for the SQLite files (removed afterwards)")->capture_default_str();
    CLI11_PARSE(app, argc, argv);

    char pattern[] = "tgw-log-bench.XXXXXX";
    const fs::path work = fs::path(dir) / pattern;
    std::string work_text = work.string();
    if (mkdtemp(work_text.data()) == nullptr) {
        std::fprintf(stderr, "robot_log_bench: --dir %s: cannot create a directory there\n", dir.c_str());
        return 2;
    }
    std::printf("on-robot log: rows appended by one thread as fast as it can, until committed (WAL, batched), %s\n",
                work_text.c_str());
    std::printf("%8s %9s %12s %10s %12s %10s %8s %9s\n", "bytes", "rows", "rows/s", "MiB/s", "append50_us",
                "append99_us", "lost", "file_MiB");
    for (std::size_t size : sizes) {
        const std::size_t n =
            std::min(rows, std::max<std::size_t>(1000, (std::size_t{1} << 30) / std::max<std::size_t>(size, 1)));
        const fs::path file = fs::path(work_text) / ("log-" + std::to_string(size) + ".db");
        const Result r = absorb(file, size, n);
        std::printf("%8zu %9zu %12.0f %10.1f %12.2f %10.2f %8llu %9.1f\n", size, n, r.rows_per_s, r.mib_per_s,
                    r.append_median_us, r.append_p99_us, static_cast<unsigned long long>(r.errors), r.file_mib);
    }
    fs::remove_all(work_text);
    return 0;
}
