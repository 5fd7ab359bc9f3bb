#include "gateway/dds/repair_desk.hpp"

#include <algorithm>
#include <array>
#include <cstring>
#include <utility>

#include "core/wire_model.hpp"
#include "gateway/dds/gap_for_repair.hpp"
#include "gateway/dds/writer_announcement.hpp"
#include "wire/rtps_submessage.hpp"

namespace tgw::dds {

namespace {

thread_local RepairDesk::WriteScope* current_scope = nullptr;
thread_local RepairDesk::PacedWatch* current_watch = nullptr;

/// Samples looked at per message: a repair message holds a few (a burst of small samples, or fragments).
constexpr std::size_t MAX_REFS = 32;

std::uint32_t entity_id(const std::array<std::uint8_t, 4>& writer) {
    return static_cast<std::uint32_t>(writer[0]) << 24 | static_cast<std::uint32_t>(writer[1]) << 16 |
           static_cast<std::uint32_t>(writer[2]) << 8 | writer[3];
}
/// Between the deadlines of an announcement's copies.
constexpr std::chrono::milliseconds ANNOUNCEMENT_STAGGER{250};
/// How often what is past its deadline is forgotten.
constexpr std::chrono::seconds PRUNE_PERIOD{1};

}  // namespace

RepairDesk::WriteScope::WriteScope(core::TopicId topic, base::SteadyTime deadline, bool reliable, bool latched,
                                   std::size_t payload_bytes)
    : topic_(topic),
      deadline_(deadline),
      reliable_(reliable),
      latched_(latched),
      payload_bytes_(payload_bytes),
      outer_(current_scope) {
    current_scope = this;
}

RepairDesk::WriteScope::~WriteScope() {
    current_scope = outer_;
}

RepairDesk::PacedWatch::PacedWatch() : outer_(current_watch) {
    current_watch = this;
}

RepairDesk::PacedWatch::~PacedWatch() {
    current_watch = outer_;
}

bool RepairDesk::PacedWatch::holding_here() {
    return current_watch != nullptr && current_watch->sample_ != 0;
}

RepairDesk::RepairDesk(std::shared_ptr<DatagramCoalescer> coalescer, const base::Clock& clock, bool samples)
    : coalescer_(std::move(coalescer)), clock_(clock), samples_(samples) {}

void RepairDesk::set_submit(std::function<void(const core::Repair&)> submit) {
    std::lock_guard<std::mutex> lock(mutex_);
    submit_ = std::move(submit);
}

void RepairDesk::stop() {
    std::lock_guard<std::mutex> lock(mutex_);
    stopped_ = true;
    submit_ = nullptr;
    counts_.discarded += held_.size();
    held_.clear();
    written_.clear();
}

void RepairDesk::forget(const DatagramSender& sender) {
    std::lock_guard<std::mutex> lock(mutex_);
    for (auto it = held_.begin(); it != held_.end();) {
        if (it->second.sender == &sender) {
            ++counts_.discarded;
            it = held_.erase(it);
        } else {
            ++it;
        }
    }
    written_.clear();  // the new participant's writers number their samples afresh
    skipped_.erase(std::remove_if(skipped_.begin(), skipped_.end(),
                                  [&](const SkippedAnnouncements& s) { return s.sender == &sender; }),
                   skipped_.end());
}

bool RepairDesk::note_scheduled(DatagramSender& sender, const DatagramDestination& destination,
                                const std::uint8_t* message, std::size_t size, std::size_t copies,
                                std::size_t prepaid_bytes) {
    WriteScope* scope = current_scope;
    const bool pacing = pace_fragments_.load(std::memory_order_relaxed);
    if (scope == nullptr || !samples_ || (!scope->reliable_ && !pacing)) {
        return false;  // a best-effort sample on a fast link: nothing to read in it
    }
    std::array<RtpsSampleRef, MAX_REFS> refs;
    const std::size_t n = rtps_sample_refs(message, size, refs.data(), refs.size());
    if (n == 0) {
        return false;
    }
    const RtpsSampleRef& written = scope->written_ ? *scope->written_ : *(scope->written_ = refs[0]);
    // Only the rest of the written sample, alone in its message: the fragments Fast DDS sends after its first.
    const bool continuation =
        pacing && copies > 0 &&
        std::all_of(refs.begin(), refs.begin() + static_cast<std::ptrdiff_t>(n), [&](const RtpsSampleRef& ref) {
            return ref.first_fragment > 1 && ref.writer == written.writer && ref.sequence == written.sequence;
        });
    if (!scope->reliable_ && !continuation) {
        return false;
    }
    const base::SteadyTime now = clock_.now();
    std::lock_guard<std::mutex> lock(mutex_);  // submitted under it, as in hold()
    if (stopped_ || !submit_) {
        return false;
    }
    if (scope->reliable_) {
        for (std::size_t i = 0; i < n; ++i) {
            written_.note(entity_id(refs[i].writer), refs[i].sequence, {scope->topic_, scope->deadline_},
                          !scope->latched_);
        }
        prune_nts(now);
    }
    if (!continuation) {
        return false;
    }
    core::Repair repair;
    repair.topic = scope->topic_;
    repair.deadline = scope->deadline_;
    repair.wire_bits = 8u * copies * (size + core::WireModel::FRAME_HEADER_BYTES);
    repair.kind = core::Repair::Kind::continuation;
    repair.prepaid_bits = 8u * prepaid_bytes;
    if (scope->paced_sample_ == 0) {
        scope->paced_sample_ = next_paced_sample_++;
    }
    repair.sample = scope->paced_sample_;
    repair.sample_payload_bytes = scope->payload_bytes_;
    if (current_watch != nullptr) {
        current_watch->sample_ = repair.sample;
        ++current_watch->continuations_;
    }
    ++counts_.continuations_held;
    hold_nts(repair, sender, destination, message, size, refs[0]);
    return true;
}

RepairDesk::Verdict RepairDesk::hold(DatagramSender& sender, const DatagramDestination& destination,
                                     const std::uint8_t* message, std::size_t size, std::size_t copies,
                                     std::vector<std::uint8_t>& gap) {
    if (!samples_) {
        return Verdict::send;  // compact mode: nothing was noted to repair, so no need to read the message
    }
    std::array<RtpsSampleRef, MAX_REFS> refs;
    const std::size_t n = rtps_sample_refs(message, size, refs.data(), refs.size());
    if (n == 0 || copies == 0) {
        return Verdict::send;
    }
    const base::SteadyTime now = clock_.now();
    core::Repair repair;
    // Submitted under the lock, so that stop() returns only once no repair is on its way to the scheduler. The
    // scheduler's loop never calls the desk with its own lock held.
    std::lock_guard<std::mutex> lock(mutex_);
    if (stopped_ || !submit_) {
        return Verdict::send;
    }
    // The message goes with its most urgent sample: the others ride along.
    const WrittenSamples::Written* owner = nullptr;
    for (std::size_t i = 0; i < n; ++i) {
        const WrittenSamples::Written* written = written_.find(entity_id(refs[i].writer), refs[i].sequence, now);
        if (written != nullptr && (owner == nullptr || written->deadline < owner->deadline)) {
            owner = written;
        }
    }
    if (owner == nullptr) {
        // None due any more. Every one a volatile reliable writer's: past its deadline, and no use to the reader.
        const bool past_deadline =
            std::all_of(refs.begin(), refs.begin() + static_cast<std::ptrdiff_t>(n),
                        [&](const RtpsSampleRef& ref) { return written_.expiring(entity_id(ref.writer)); });
        if (past_deadline && gap_for_repair(message, size, gap)) {
            ++counts_.gapped;
            return Verdict::gap;
        }
        return Verdict::send;  // not a sample of a scheduled write (discovery), or a latched one for a late joiner
    }
    const bool repeat = std::any_of(held_.begin(), held_.end(), [&](const auto& entry) {
        return entry.second.first == refs[0] && entry.second.destination == destination;
    });
    if (repeat) {
        ++counts_.repeats;
        return Verdict::held;
    }
    repair.topic = owner->topic;
    repair.deadline = owner->deadline;
    repair.wire_bits = 8u * copies * (size + core::WireModel::FRAME_HEADER_BYTES);
    ++counts_.held;
    hold_nts(repair, sender, destination, message, size, refs[0]);
    return Verdict::held;
}

bool RepairDesk::hold_announcement(DatagramSender& sender, const DatagramDestination& destination,
                                   const std::uint8_t* message, std::size_t size, const LocatorFilter& supported) {
    std::array<RtpsSampleRef, MAX_REFS> refs;
    const std::size_t n = rtps_sample_refs(message, size, refs.data(), refs.size());
    const auto announces = [](const RtpsSampleRef& ref) {
        return std::memcmp(ref.writer.data(), wire::rtps_bytes::SPDP_WRITER_ID,
                           sizeof(wire::rtps_bytes::SPDP_WRITER_ID)) == 0;
    };
    if (std::none_of(refs.begin(), refs.begin() + static_cast<std::ptrdiff_t>(n), announces)) {
        return false;
    }
    std::vector<DatagramDestination> copies;
    for (const eprosima::fastrtps::rtps::Locator_t& locator : destination.locators) {
        DatagramDestination copy{destination.channel, {locator}};
        if (supported(locator) && std::find(copies.begin(), copies.end(), copy) == copies.end()) {
            copies.push_back(std::move(copy));
        }
    }
    if (copies.empty()) {
        return false;
    }
    const base::SteadyTime now = clock_.now();
    std::lock_guard<std::mutex> lock(mutex_);  // submitted under it, as in hold()
    if (stopped_ || !submit_) {
        return false;
    }
    base::Duration stagger{};
    for (DatagramDestination& copy : copies) {
        const auto held_for = std::find_if(held_.begin(), held_.end(), [&](const auto& entry) {
            return entry.second.kind == core::Repair::Kind::announcement && entry.second.sender == &sender &&
                   entry.second.destination == copy;
        });
        if (held_for != held_.end()) {
            held_for->second.bytes.assign(message, message + size);  // the participant as it is now
            ++counts_.announcements_replaced;
            continue;
        }
        core::Repair repair;
        // Copies the schedule found no room for leave at their deadlines: one at a time, not in a burst.
        repair.deadline = now + core::ANNOUNCEMENT_WAIT + stagger;
        stagger += ANNOUNCEMENT_STAGGER;
        repair.wire_bits = 8u * (size + core::WireModel::FRAME_HEADER_BYTES);
        repair.kind = core::Repair::Kind::announcement;
        repair.skippable = skipped_in_a_row_nts(sender, copy) < core::MAX_SKIPPED_ANNOUNCEMENTS;
        ++counts_.announcements_held;
        hold_nts(repair, sender, std::move(copy), message, size, RtpsSampleRef{});
    }
    return true;
}

void RepairDesk::set_topic_lookup(TopicLookup lookup) {
    std::lock_guard<std::mutex> lock(mutex_);
    topic_lookup_ = std::move(lookup);
}

bool RepairDesk::hold_writer_announcement(DatagramSender& sender, const DatagramDestination& destination,
                                          const std::uint8_t* message, std::size_t size, std::size_t copies) {
    if (!samples_ || copies == 0) {
        return false;
    }
    const std::optional<WriterAnnouncements> announcement = writer_announcements(message, size);
    if (!announcement) {
        return false;
    }
    const base::SteadyTime now = clock_.now();
    std::lock_guard<std::mutex> lock(mutex_);  // submitted under it, as in hold()
    if (stopped_ || !submit_ || !topic_lookup_) {
        return false;
    }
    // Several in one message go in the urgency of the most urgent.
    std::optional<ScheduledTopic> topic;
    for (std::size_t i = 0; i < announcement->count; ++i) {
        const std::optional<ScheduledTopic> found = topic_lookup_(announcement->topics[i]);
        if (found && (!topic || found->ttl < topic->ttl)) {
            topic = found;
        }
    }
    if (!topic) {
        return false;
    }
    const bool repeat = std::any_of(held_.begin(), held_.end(), [&](const auto& entry) {
        return entry.second.kind == core::Repair::Kind::writer_announcement &&
               entry.second.first == announcement->first && entry.second.destination == destination;
    });
    if (repeat) {
        ++counts_.repeats;
        return true;
    }
    core::Repair repair;
    repair.topic = topic->topic;
    repair.deadline = now + std::min(topic->ttl, core::ANNOUNCEMENT_WAIT);
    repair.wire_bits = 8u * copies * (size + core::WireModel::FRAME_HEADER_BYTES);
    repair.kind = core::Repair::Kind::writer_announcement;
    ++counts_.writer_announcements_held;
    hold_nts(repair, sender, destination, message, size, announcement->first);
    return true;
}

void RepairDesk::hold_nts(core::Repair repair, DatagramSender& sender, DatagramDestination destination,
                          const std::uint8_t* message, std::size_t size, const RtpsSampleRef& first) {
    repair.id = next_id_++;
    Held& held = held_[repair.id];
    held.sender = &sender;
    held.destination = std::move(destination);
    held.bytes.assign(message, message + size);
    held.first = first;
    held.kind = repair.kind;
    held.sample = repair.sample;
    submit_(repair);
}

std::uint64_t RepairDesk::send(std::uint64_t id) {
    Held held;
    {
        std::lock_guard<std::mutex> lock(mutex_);
        const auto it = held_.find(id);
        if (it == held_.end()) {
            return 0;  // stopped meanwhile
        }
        held = std::move(it->second);
        held_.erase(it);
    }
    const bool ok = coalescer_->send(*held.sender, held.destination, held.bytes.data(), held.bytes.size());
    std::lock_guard<std::mutex> lock(mutex_);
    ++(ok ? counts_.sent : counts_.send_failures);
    if (held.kind == core::Repair::Kind::announcement) {
        skipped_in_a_row_nts(*held.sender, held.destination) = 0;
    }
    return held.sample;
}

void RepairDesk::discard(std::uint64_t id) {
    std::lock_guard<std::mutex> lock(mutex_);
    const auto it = held_.find(id);
    if (it == held_.end()) {
        return;
    }
    if (it->second.kind == core::Repair::Kind::announcement) {
        ++skipped_in_a_row_nts(*it->second.sender, it->second.destination);  // the next one to it goes
    }
    ++counts_.discarded;
    held_.erase(it);
}

int& RepairDesk::skipped_in_a_row_nts(const DatagramSender& sender, const DatagramDestination& destination) {
    const auto it = std::find_if(skipped_.begin(), skipped_.end(), [&](const SkippedAnnouncements& s) {
        return s.sender == &sender && s.destination == destination;
    });
    if (it != skipped_.end()) {
        return it->in_a_row;
    }
    skipped_.push_back({&sender, destination, 0});
    return skipped_.back().in_a_row;
}

RepairDesk::Counts RepairDesk::counts() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return counts_;
}

void RepairDesk::prune_nts(base::SteadyTime now) {
    if (now < next_prune_) {
        return;
    }
    next_prune_ = now + PRUNE_PERIOD;
    written_.prune(now);
}

}  // namespace tgw::dds
