// Fast DDS's own log lines through the program's reporting: one line each, without the terminal colour codes
// its default consumer prints, and what to do where the message is one we know.
#pragma once

#include <cstdint>
#include <map>
#include <mutex>
#include <ostream>
#include <string>

#include <fastdds/dds/log/Log.hpp>

#include <functional>

#include "base/time.hpp"

namespace tgw::base {

/// `text` as one plain line: terminal escape sequences (ESC [ ... final letter) removed, line breaks and tabs
/// as spaces, no trailing space.
std::string plain_line(const std::string& text);

/// What a person should do about the Fast DDS message `message`; empty when it is not one we know.
std::string fastdds_advice(const std::string& message);

/// Prints each Fast DDS log entry as "PROGRAM: Fast DDS error (CATEGORY): MESSAGE; ADVICE". Fast DDS can repeat
/// one message for every datagram: the same category and message again within `quiet` of its last line is
/// counted, and the next line printed for it says how many were not.
class FastDdsLogReporter final : public eprosima::fastdds::dds::LogConsumer {
  public:
    /// `now` is injected for tests.
    FastDdsLogReporter(std::string program, std::ostream& out, Duration quiet = std::chrono::seconds(10),
                       std::function<SteadyTime()> now = SteadyClock::now);

    void Consume(const eprosima::fastdds::dds::Log::Entry& entry) override;

  private:
    struct Seen {
        SteadyTime printed;
        std::uint64_t unprinted = 0;
    };

    const std::string program_;
    std::ostream& out_;
    const Duration quiet_;
    const std::function<SteadyTime()> now_;
    std::mutex mutex_;
    std::map<std::string, Seen> seen_;
};

/// Replaces Fast DDS's log consumers (coloured lines on stdout) with a FastDdsLogReporter to std::cerr for
/// `program` (Fast DDS's verbosity stays: errors only). Call once, before the first participant.
void report_fastdds_log_as(const std::string& program);

}  // namespace tgw::base
