#pragma once

#include <atomic>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include <fastdds/dds/log/Log.hpp>

namespace tgw::test {

/// A Fast DDS log consumer that counts entries at Error level and keeps their text, so a test can fail when
/// Fast DDS logged an error (DDS Router's log tester idea). Register once per process; Fast DDS owns it.
class ErrorLogCounter final : public eprosima::fastdds::dds::LogConsumer {
  public:
    void Consume(const eprosima::fastdds::dds::Log::Entry& entry) override {
        if (entry.kind != eprosima::fastdds::dds::Log::Kind::Error) {
            return;
        }
        std::lock_guard<std::mutex> lock(mutex_);
        errors_.push_back(std::string(entry.context.category ? entry.context.category : "") + ": " + entry.message);
    }

    /// The errors logged since the last call, after Fast DDS's log thread has caught up.
    std::vector<std::string> take_errors() {
        eprosima::fastdds::dds::Log::Flush();
        std::lock_guard<std::mutex> lock(mutex_);
        std::vector<std::string> out;
        out.swap(errors_);
        return out;
    }

    /// The process-wide instance, registered with Fast DDS on first use.
    static ErrorLogCounter& instance() {
        static ErrorLogCounter* counter = [] {
            auto owned = std::make_unique<ErrorLogCounter>();
            ErrorLogCounter* raw = owned.get();
            eprosima::fastdds::dds::Log::RegisterConsumer(std::move(owned));
            return raw;
        }();
        return *counter;
    }

  private:
    std::mutex mutex_;
    std::vector<std::string> errors_;
};

}  // namespace tgw::test
