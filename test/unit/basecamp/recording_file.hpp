// A base-camp recording written through SampleStore, as tm-basecamp record writes it, for tests that read one.
#pragma once

#include <string>
#include <vector>

#include "basecamp/recording/sample_store.hpp"

namespace tgw::test {

inline void write_recording(const std::string& path, const std::vector<basecamp::TopicRecord>& topics,
                            const std::vector<basecamp::SampleRecord>& samples) {
    basecamp::SampleStore store(path, "--out", 10);
    for (const basecamp::TopicRecord& t : topics)
        store.add_topic(t);
    for (const basecamp::SampleRecord& s : samples)
        store.add(s);
    store.flush();
}

}  // namespace tgw::test
