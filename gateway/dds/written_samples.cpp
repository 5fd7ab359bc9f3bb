#include "gateway/dds/written_samples.hpp"

#include <algorithm>

namespace tgw::dds {

namespace {

template <typename Samples>
auto at_or_after(Samples& samples, std::int64_t sequence) {
    return std::lower_bound(samples.begin(), samples.end(), sequence,
                            [](const auto& entry, std::int64_t s) { return entry.sequence < s; });
}

}  // namespace

void WrittenSamples::note(std::uint32_t writer, std::int64_t sequence, const Written& written, bool expiring) {
    Writer& w = writers_[writer];
    w.expiring = w.expiring || expiring;
    if (w.samples.empty() || w.samples.back().sequence < sequence) {
        w.samples.push_back(Entry{sequence, written});  // the usual case: the writer's newest
        return;
    }
    const auto it = at_or_after(w.samples, sequence);
    if (it != w.samples.end() && it->sequence == sequence) {
        it->written = written;
    } else {
        w.samples.insert(it, Entry{sequence, written});
    }
}

const WrittenSamples::Written* WrittenSamples::find(std::uint32_t writer, std::int64_t sequence,
                                                    base::SteadyTime now) const {
    const auto w = writers_.find(writer);
    if (w == writers_.end()) {
        return nullptr;
    }
    const auto it = at_or_after(w->second.samples, sequence);
    if (it == w->second.samples.end() || it->sequence != sequence || it->written.deadline <= now) {
        return nullptr;
    }
    return &it->written;
}

bool WrittenSamples::expiring(std::uint32_t writer) const {
    const auto w = writers_.find(writer);
    return w != writers_.end() && w->second.expiring;
}

void WrittenSamples::prune(base::SteadyTime now) {
    for (auto& [id, w] : writers_) {
        while (!w.samples.empty() && w.samples.front().written.deadline <= now) {
            w.samples.pop_front();
        }
    }
}

std::size_t WrittenSamples::size() const {
    std::size_t n = 0;
    for (const auto& [id, w] : writers_) {
        n += w.samples.size();
    }
    return n;
}

}  // namespace tgw::dds
