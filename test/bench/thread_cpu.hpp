// The CPU time of each thread of this process, from the kernel's scheduler statistics: which thread bounds a
// path's rate. A path through one thread cannot carry more samples a second than 1 s over that thread's CPU
// time per sample, however many cores the machine has.
#pragma once

#include <sys/types.h>

#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>

namespace tgw::bench {

/// Nanoseconds each thread of this process has run, by thread id (/proc/self/task/TID/schedstat).
class ThreadCpu {
  public:
    static ThreadCpu now() {
        ThreadCpu snapshot;
        std::error_code ec;
        for (const auto& task : std::filesystem::directory_iterator("/proc/self/task", ec)) {
            std::ifstream schedstat(task.path() / "schedstat");
            std::uint64_t run_ns = 0;
            if (schedstat >> run_ns) {
                snapshot.run_ns_[static_cast<pid_t>(std::atoll(task.path().filename().c_str()))] = run_ns;
            }
        }
        return snapshot;
    }

    /// Each thread's CPU time since `before`, in microseconds per one of `samples`; threads that ran for no
    /// measurable time are left out.
    std::map<pid_t, double> us_per_sample_since(const ThreadCpu& before, std::uint64_t samples) const {
        std::map<pid_t, double> out;
        if (samples == 0) {
            return out;
        }
        for (const auto& [tid, run_ns] : run_ns_) {
            const auto it = before.run_ns_.find(tid);
            const std::uint64_t base = it == before.run_ns_.end() ? 0 : it->second;
            if (run_ns > base) {
                out[tid] = static_cast<double>(run_ns - base) / 1e3 / static_cast<double>(samples);
            }
        }
        return out;
    }

  private:
    std::map<pid_t, std::uint64_t> run_ns_;
};

}  // namespace tgw::bench
