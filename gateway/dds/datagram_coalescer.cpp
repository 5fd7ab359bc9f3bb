#include "gateway/dds/datagram_coalescer.hpp"

#include <algorithm>

#include <atomic>
#include <optional>
#include <utility>

#include "core/wire_model.hpp"

namespace tgw::dds {

namespace {
// Every scope gets its own number, so that the messages of one write (a sample's fragments) are told apart
// from those of the next write.
std::atomic<std::uint64_t> last_scope{0};
thread_local std::uint64_t current_scope = 0;  // 0: none
}  // namespace

DatagramCoalescer::DeferScope::DeferScope() : outer_(current_scope) {
    current_scope = last_scope.fetch_add(1, std::memory_order_relaxed) + 1;
}

DatagramCoalescer::DeferScope::~DeferScope() {
    current_scope = outer_;
}

std::uint64_t DatagramCoalescer::DeferScope::current() {
    return current_scope;
}

DatagramCoalescer::DatagramCoalescer(std::chrono::microseconds window, std::size_t max_datagram_bytes,
                                     const base::Clock& clock, HeldControl held_control)
    : window_(window), max_datagram_bytes_(max_datagram_bytes), clock_(clock), held_control_(std::move(held_control)) {}

DatagramCoalescer::~DatagramCoalescer() {
    stop();
}

void DatagramCoalescer::start() {
    std::lock_guard<std::mutex> lock(mutex_);
    if (!thread_.joinable() && !stopping_) {
        thread_ = std::thread([this] { run(); });
    }
}

void DatagramCoalescer::forget(const DatagramSender& sender) {
    std::unique_lock<std::mutex> lock(mutex_);
    const base::SteadyTime now = clock_.now();
    for (auto& batch : batches_) {
        if (batch->sender == &sender)
            flush_nts(*batch, now);
    }
    batches_.erase(std::remove_if(batches_.begin(), batches_.end(),
                                  [&](const std::unique_ptr<Batch>& batch) { return batch->sender == &sender; }),
                   batches_.end());
    report_charges(lock);
}

void DatagramCoalescer::stop() {
    {
        std::lock_guard<std::mutex> lock(mutex_);
        if (stopped_) {
            return;
        }
        stopping_ = true;
    }
    wake_.notify_all();
    if (thread_.joinable()) {
        thread_.join();
    }
    std::unique_lock<std::mutex> lock(mutex_);
    const base::SteadyTime now = clock_.now();
    for (auto& batch : batches_) {
        flush_nts(*batch, now);
    }
    stopped_ = true;
    report_charges(lock);
}

DatagramCoalescer::Batch* DatagramCoalescer::find_nts(const DatagramSender& sender,
                                                      const DatagramDestination& destination) {
    for (auto& batch : batches_) {
        if (batch->sender == &sender && batch->destination == destination) {
            return batch.get();
        }
    }
    return nullptr;
}

DatagramCoalescer::Batch& DatagramCoalescer::batch_for_nts(DatagramSender& sender,
                                                           const DatagramDestination& destination) {
    if (Batch* batch = find_nts(sender, destination)) {
        return *batch;
    }
    auto batch = std::make_unique<Batch>(max_datagram_bytes_);
    batch->sender = &sender;
    batch->destination = destination;
    // Never sent to: the first message goes at once.
    batch->last_sent = clock_.now() - window_;
    batches_.push_back(std::move(batch));
    return *batches_.back();
}

bool DatagramCoalescer::fills_datagram(std::size_t size) const {
    return size + max_datagram_bytes_ / FULL_DATAGRAM_ROOM_FRACTION > max_datagram_bytes_;
}

bool DatagramCoalescer::send_now_nts(Batch& batch, const std::uint8_t* bytes, std::size_t size, base::SteadyTime now) {
    batch.last_sent = now;
    ++counts_.datagrams;
    return batch.sender->send_datagram(batch.destination, bytes, size);
}

void DatagramCoalescer::flush_nts(Batch& batch, base::SteadyTime now) {
    if (batch.datagram.empty()) {
        return;
    }
    if (batch.control_only) {
        // Nothing came to ride with: a datagram of their own, not one of the samples' (counts_.datagrams).
        pending_charge_ += batch.copies * (batch.datagram.size() + core::WireModel::FRAME_HEADER_BYTES);
        batch.control_only = false;
        batch.control_messages = 0;
        batch.sender->send_datagram(batch.destination, batch.datagram.data(), batch.datagram.size());
        batch.datagram.clear();
        return;
    }
    if (!send_now_nts(batch, batch.datagram.data(), batch.datagram.size(), now)) {
        ++counts_.failed_datagrams;
    }
    batch.datagram.clear();
}

std::optional<bool> DatagramCoalescer::send_with_held_control_nts(Batch& batch, const std::uint8_t* message,
                                                                  std::size_t size) {
    if (!batch.datagram.append(message, size)) {
        return std::nullopt;
    }
    // The message is charged as if alone (size and frames); the datagram carries it and theirs in fewer bytes
    // (one header, one INFO_DST to the base camp): theirs cost the rest.
    pending_charge_ += batch.copies * (batch.datagram.size() - std::min(batch.datagram.size(), size));
    counts_.controls_rode += batch.control_messages;
    batch.control_only = false;
    batch.control_messages = 0;
    const bool sent = batch.sender->send_datagram(batch.destination, batch.datagram.data(), batch.datagram.size());
    batch.datagram.clear();
    return sent;
}

bool DatagramCoalescer::hold(DatagramSender& sender, const DatagramDestination& destination,
                             const std::uint8_t* message, std::size_t size, std::size_t copies) {
    std::unique_lock<std::mutex> lock(mutex_);
    if (!holds_control() || stopping_) {
        pending_charge_ += copies * (size + core::WireModel::FRAME_HEADER_BYTES);
        if (Batch* batch = find_nts(sender, destination)) {
            flush_nts(*batch, clock_.now());
        }
        const bool sent = sender.send_datagram(destination, message, size);
        report_charges(lock);
        return sent;
    }
    Batch& batch = batch_for_nts(sender, destination);
    const base::SteadyTime now = clock_.now();
    ++counts_.controls_held;
    if (!batch.datagram.empty() && !batch.control_only) {
        // Samples wait for their window: it rides with them.
        const std::size_t before = batch.datagram.size();
        if (batch.datagram.append(message, size)) {
            pending_charge_ += copies * (batch.datagram.size() - before);
            ++counts_.controls_rode;
            report_charges(lock);
            return true;
        }
        flush_nts(batch, now);
    }
    if (!batch.datagram.append(message, size)) {
        flush_nts(batch, now);
        if (!batch.datagram.append(message, size)) {
            pending_charge_ += copies * (size + core::WireModel::FRAME_HEADER_BYTES);
            const bool sent = send_now_nts(batch, message, size, now);
            report_charges(lock);
            return sent;
        }
    }
    if (!batch.control_only) {
        batch.control_only = true;
        batch.copies = copies;
        batch.deadline = now + held_control_.wait;
        kicked_ = true;
    }
    ++batch.control_messages;
    report_charges(lock);
    wake_.notify_one();
    return true;
}

void DatagramCoalescer::report_charges(std::unique_lock<std::mutex>& lock) {
    const std::uint64_t charge = std::exchange(pending_charge_, 0);
    if (charge == 0 || !held_control_.on_sent) {
        return;
    }
    // Outside the lock: the callback charges the scheduler, whose writes come back here.
    lock.unlock();
    held_control_.on_sent(charge);
    lock.lock();
}

bool DatagramCoalescer::send(DatagramSender& sender, const DatagramDestination& destination,
                             const std::uint8_t* message, std::size_t size) {
    std::unique_lock<std::mutex> lock(mutex_);
    const bool sent = send_nts(lock, sender, destination, message, size);
    report_charges(lock);
    return sent;
}

bool DatagramCoalescer::send_nts(std::unique_lock<std::mutex>& lock, DatagramSender& sender,
                                 const DatagramDestination& destination, const std::uint8_t* message,
                                 std::size_t size) {
    const std::uint64_t scope = DeferScope::current();
    if (scope == 0 || stopping_) {
        // What waits for this destination was written first: it goes first, with this message when it can.
        if (Batch* batch = find_nts(sender, destination)) {
            if (batch->control_only) {
                if (const std::optional<bool> sent = send_with_held_control_nts(*batch, message, size)) {
                    return *sent;
                }
            }
            flush_nts(*batch, clock_.now());
        }
        return sender.send_datagram(destination, message, size);
    }
    Batch& batch = batch_for_nts(sender, destination);
    const base::SteadyTime now = clock_.now();
    ++counts_.messages;
    if (batch.control_only) {
        // A sample: it goes at once, and what was held goes in its datagram.
        if (const std::optional<bool> sent = send_with_held_control_nts(batch, message, size)) {
            ++counts_.datagrams;
            batch.last_sent = now;
            batch.sent_at_once_scope = scope;
            return *sent;
        }
        flush_nts(batch, now);
    }
    // A message that fills its datagram goes at once, after what waits: nothing could share its datagram, and
    // holding it would cost a copy and a wake-up of the flush thread (a large sample's fragments on a fast link).
    // The rest of its write follows it.
    if (fills_datagram(size)) {
        flush_nts(batch, now);
        batch.sent_at_once_scope = scope;
        return send_now_nts(batch, message, size, now);
    }
    // A sample that comes alone goes at once, all its fragments; with a zero window every sample does.
    if (batch.datagram.empty() && (now - batch.last_sent >= window_ || batch.sent_at_once_scope == scope)) {
        batch.sent_at_once_scope = scope;
        return send_now_nts(batch, message, size, now);
    }
    if (!batch.datagram.append(message, size)) {
        flush_nts(batch, now);
        if (!batch.datagram.append(message, size)) {
            return send_now_nts(batch, message, size, now);  // larger than a datagram: Fast DDS's size rules
        }
    }
    if (batch.datagram.messages() == 1) {
        batch.deadline = now + window_;
        kicked_ = true;
        lock.unlock();
        wake_.notify_one();
        lock.lock();
    }
    return true;
}

void DatagramCoalescer::flush_due() {
    std::unique_lock<std::mutex> lock(mutex_);
    flush_due_nts(clock_.now());
    report_charges(lock);
}

void DatagramCoalescer::flush_due_nts(base::SteadyTime now) {
    for (auto& batch : batches_) {
        if (!batch->datagram.empty() && batch->deadline <= now) {
            flush_nts(*batch, now);
        }
    }
}

void DatagramCoalescer::run() {
    std::unique_lock<std::mutex> lock(mutex_);
    while (!stopping_) {
        std::optional<base::SteadyTime> next;
        for (const auto& batch : batches_) {
            if (!batch->datagram.empty() && (!next || batch->deadline < *next)) {
                next = batch->deadline;
            }
        }
        // The clock is injected, but waiting needs real time.
        if (next) {
            wake_.wait_for(lock, *next - clock_.now(), [this] { return stopping_ || kicked_; });
        } else {
            wake_.wait(lock, [this] { return stopping_ || kicked_; });
        }
        kicked_ = false;
        flush_due_nts(clock_.now());
        report_charges(lock);
    }
}

DatagramCoalescer::Counts DatagramCoalescer::counts() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return counts_;
}

}  // namespace tgw::dds
