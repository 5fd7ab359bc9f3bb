#pragma once

#include <atomic>
#include <cstdint>
#include <functional>
#include <map>
#include <string>

#include "base/time.hpp"

namespace tgw::basecamp {

/// A status line for long commands: redrawn in place on stderr when stderr is a terminal, nothing otherwise
/// (scripts and logs stay quiet).
class ProgressLine {
  public:
    ProgressLine();
    /// Ends the line, so that what follows starts on its own.
    ~ProgressLine();
    ProgressLine(const ProgressLine&) = delete;
    ProgressLine& operator=(const ProgressLine&) = delete;

    void show(const std::string& text);

  private:
    const bool terminal_;
    bool shown_ = false;
};

/// Runs `step(slice)` in slices of at most a second until `duration` has passed or `stop` turns true, and shows
/// `line()` on a ProgressLine after each slice.
void run_with_progress(base::Duration duration, const std::atomic<bool>& stop,
                       const std::function<void(base::Duration)>& step, const std::function<std::string()>& line);

/// "N topics, M samples" for a progress line, from per-topic sample counts.
std::string topics_and_samples(const std::map<std::string, std::uint64_t>& counts);

}  // namespace tgw::basecamp
