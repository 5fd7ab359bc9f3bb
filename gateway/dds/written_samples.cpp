#include "gateway/dds/written_samples.hpp"

#include <algorithm>
#include <iterator>

namespace tgw::dds {

namespace {

template <typename Samples>
auto at_or_after(Samples& samples, std::int64_t sequence) {
    return std::lower_bound(samples.begin(), samples.end(), sequence,
                            [](const auto& entry, std::int64_t s) { return entry.sequence < s; });
}

}  // namespace

void WrittenSamples::note(std::uint32_t writer, std::int64_t sequence, const Written& written, bool expiring) {
    if (expiring) {
        expiring_.insert(writer);
    }
    std::deque<Entry>& samples = writers_[writer];
    if (samples.empty() || samples.back().sequence < sequence) {
        samples.push_back(Entry{sequence, written});  // the usual case: the writer's newest
        return;
    }
    const auto it = at_or_after(samples, sequence);
    if (it != samples.end() && it->sequence == sequence) {
        it->written = written;
    } else {
        samples.insert(it, Entry{sequence, written});
    }
}

const WrittenSamples::Written* WrittenSamples::find(std::uint32_t writer, std::int64_t sequence,
                                                    base::SteadyTime now) const {
    const auto w = writers_.find(writer);
    if (w == writers_.end()) {
        return nullptr;
    }
    const auto it = at_or_after(w->second, sequence);
    if (it == w->second.end() || it->sequence != sequence || it->written.deadline <= now) {
        return nullptr;
    }
    return &it->written;
}

bool WrittenSamples::expiring(std::uint32_t writer) const {
    return expiring_.count(writer) > 0;
}

void WrittenSamples::prune(base::SteadyTime now) {
    for (auto w = writers_.begin(); w != writers_.end();) {
        std::deque<Entry>& samples = w->second;
        while (!samples.empty() && samples.front().written.deadline <= now) {
            samples.pop_front();
        }
        w = samples.empty() ? writers_.erase(w) : std::next(w);
    }
}

std::size_t WrittenSamples::size() const {
    std::size_t n = 0;
    for (const auto& [id, samples] : writers_) {
        n += samples.size();
    }
    return n;
}

}  // namespace tgw::dds
