#include "basecamp/cli/progress_line.hpp"

#include <unistd.h>

#include <algorithm>
#include <cstdio>

namespace tgw::basecamp {

ProgressLine::ProgressLine() : terminal_(isatty(STDERR_FILENO) != 0) {}

ProgressLine::~ProgressLine() {
    if (shown_) {
        std::fputc('\n', stderr);
    }
}

void ProgressLine::show(const std::string& text) {
    if (!terminal_) {
        return;
    }
    // Back to the start of the line, clear it, write; no newline until the end.
    std::fprintf(stderr, "\r\x1b[K%s", text.c_str());
    std::fflush(stderr);
    shown_ = true;
}

void run_with_progress(base::Duration duration, const std::atomic<bool>& stop,
                       const std::function<void(base::Duration)>& step, const std::function<std::string()>& line) {
    ProgressLine progress;
    const base::SteadyTime start = base::SteadyClock::now();
    const base::SteadyTime end =
        duration >= base::SteadyTime::max() - start ? base::SteadyTime::max() : start + duration;
    while (!stop.load()) {
        const base::SteadyTime now = base::SteadyClock::now();
        if (now >= end) {
            break;
        }
        step(std::min<base::Duration>(std::chrono::seconds(1), end - now));
        progress.show(line());
    }
}

std::string topics_and_samples(const std::map<std::string, std::uint64_t>& counts) {
    std::uint64_t samples = 0;
    for (const auto& [topic, count] : counts)
        samples += count;
    return std::to_string(counts.size()) + " topics, " + std::to_string(samples) + " samples";
}

}  // namespace tgw::basecamp
