#include "base/fastdds_log_reporter.hpp"

#include <iostream>
#include <memory>
#include <utility>
#include <vector>

namespace tgw::base {

namespace {

using eprosima::fastdds::dds::Log;

struct KnownMessage {
    const char* contains;
    const char* advice;
};

// The messages a user of the gateway and the camp's tools has met, with what to do about each.
const std::vector<KnownMessage>& known_messages() {
    static const std::vector<KnownMessage> known = {
        {"All whitelist interfaces were filtered out",
         "the interface this participant was bound to is down or has no IPv4 address now, and Fast DDS checks it "
         "only at start: bring it up and restart, or name another interface"},
        {"Error joining multicast group",
         "the interface cannot join multicast (no route for 239.255.0.0/16, or multicast off): discovery needs "
         "peers (--peer) or a discovery server on it"},
        {"Couldn't open port", "shared memory (/dev/shm) is full or not writable: Fast DDS goes on over UDP"},
        {"Failed to create segment", "shared memory (/dev/shm) is full or not writable: Fast DDS goes on over UDP"},
        {"Couldn't add matched reader due to resource limits",
         "a writer has more readers than its resource limits allow: the rest get nothing from it"},
    };
    return known;
}

const char* kind_name(Log::Kind kind) {
    switch (kind) {
        case Log::Kind::Error:
            return "error";
        case Log::Kind::Warning:
            return "warning";
        case Log::Kind::Info:
            return "info";
    }
    return "message";
}

}  // namespace

std::string plain_line(const std::string& text) {
    std::string line;
    line.reserve(text.size());
    for (std::size_t i = 0; i < text.size(); ++i) {
        const char c = text[i];
        if (c == '\x1b') {
            // CSI: ESC '[' parameters, up to a final byte in '@'..'~'
            if (i + 1 < text.size() && text[i + 1] == '[') {
                i += 2;
                while (i < text.size() && (text[i] < '@' || text[i] > '~'))
                    ++i;
            }
            continue;
        }
        if (c == '\n' || c == '\r' || c == '\t') {
            if (!line.empty() && line.back() != ' ')
                line.push_back(' ');
            continue;
        }
        line.push_back(c);
    }
    while (!line.empty() && line.back() == ' ')
        line.pop_back();
    return line;
}

std::string fastdds_advice(const std::string& message) {
    for (const KnownMessage& known : known_messages()) {
        if (message.find(known.contains) != std::string::npos)
            return known.advice;
    }
    return {};
}

FastDdsLogReporter::FastDdsLogReporter(std::string program, std::ostream& out, Duration quiet,
                                       std::function<SteadyTime()> now)
    : program_(std::move(program)), out_(out), quiet_(quiet), now_(std::move(now)) {}

void FastDdsLogReporter::Consume(const Log::Entry& entry) {
    const std::string category = entry.context.category != nullptr ? plain_line(entry.context.category) : "";
    const std::string message = plain_line(entry.message);
    const SteadyTime now = now_();
    std::lock_guard<std::mutex> lock(mutex_);
    auto [seen, first] = seen_.try_emplace(category + '\n' + message, Seen{now, 0});
    if (!first) {
        if (now - seen->second.printed < quiet_) {
            ++seen->second.unprinted;
            return;
        }
    }
    out_ << program_ << ": Fast DDS " << kind_name(entry.kind);
    if (!category.empty())
        out_ << " (" << category << ")";
    out_ << ": " << message;
    const std::string advice = fastdds_advice(message);
    if (!advice.empty())
        out_ << "; " << advice;
    if (seen->second.unprinted > 0)
        out_ << " [" << seen->second.unprinted << " more since the last such line]";
    out_ << std::endl;
    seen->second = Seen{now, 0};
}

void report_fastdds_log_as(const std::string& program) {
    Log::ClearConsumers();
    Log::RegisterConsumer(std::make_unique<FastDdsLogReporter>(program, std::cerr));
}

}  // namespace tgw::base
