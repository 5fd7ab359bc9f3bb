#include "basecamp/capture/delivery_tally.hpp"

#include <algorithm>

namespace tgw::basecamp {

std::string prefix_text(const ParticipantPrefix& prefix) {
    static constexpr char HEX[] = "0123456789abcdef";
    std::string text;
    for (std::uint8_t byte : prefix) {
        if (!text.empty())
            text += '.';
        text += HEX[byte >> 4];
        text += HEX[byte & 0xf];
    }
    return text;
}

void DeliveryTally::add(const WriterGuid& writer, std::uint64_t sequence, std::uint64_t bytes) {
    ParticipantPrefix prefix;
    std::copy_n(writer.begin(), prefix.size(), prefix.begin());
    std::lock_guard<std::mutex> lock(mutex_);
    DeliveryTotals& totals = totals_[prefix];
    totals.received_samples += 1;
    totals.received_bytes += bytes;

    auto [it, first] = writers_.try_emplace(writer);
    WriterState& state = it->second;
    if (first) {
        state.next_sequence = sequence + 1;
        return;
    }
    if (sequence >= state.next_sequence) {
        const std::uint64_t skipped = sequence - state.next_sequence;
        totals.lost_samples += skipped;
        state.open_gaps += skipped;
        state.next_sequence = sequence + 1;
    } else if (state.open_gaps > 0) {
        // Overtaken on the way: it was counted lost when its successor came.
        state.open_gaps -= 1;
        totals.lost_samples -= 1;
    }
}

std::map<ParticipantPrefix, DeliveryTotals> DeliveryTally::totals() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return totals_;
}

}  // namespace tgw::basecamp
