// Backfill on the robot's side (docs/design/backfill.md): the rows of the on-robot log that the base camp has not
// acknowledged go to the forwarding loop as its idle work, most valuable first (core::BackfillPlanner), and the
// camp's acknowledgements mark them in the log, where they are then the first freed at the cap.
#pragma once

#include <array>
#include <condition_variable>
#include <cstdint>
#include <deque>
#include <functional>
#include <mutex>
#include <optional>
#include <thread>
#include <utility>
#include <vector>

#include "BackfillPubSubTypes.h"
#include "base/clock.hpp"
#include "core/backfill_planner.hpp"
#include "core/idle_source.hpp"
#include "core/wire_model.hpp"
#include "gateway/log/robot_log.hpp"

namespace tgw::dds {

/// `row` of the log `log_id` as the backfill topic carries it.
idl::BackfillSample backfill_sample(const log::StoredSample& row, const std::array<std::uint8_t, 16>& log_id);

/// Hands the forwarding loop the log's unacknowledged rows as samples of the backfill topic (idl::BackfillSample),
/// one at a time when the loop is idle (core::IdleSource). A thread of its own reads the log ahead: the loop asks
/// under its lock and is given only what was read before. What became of each sample comes back from the sink
/// (left, not_left); the camp's acknowledgements from its reader (acknowledged).
class BackfillSender final : public core::IdleSource {
  public:
    struct Config {
        core::BackfillConfig planner;
        /// How often the log is read for new rows, and the rows read ahead for the loop.
        base::Duration poll = std::chrono::milliseconds(200);
        std::size_t page_rows = 5000;
        std::size_t read_ahead = 4;
    };

    /// `wake_loop` makes the loop ask again (core::ForwardingLoop::kick): called when a sample is ready after the
    /// loop was told none was. `wire` prices a sample on the link for the cap. `log` must outlive the sender.
    BackfillSender(log::RobotLog& log, Config config, core::WireModel wire, const base::Clock& clock,
                   std::function<void()> wake_loop);
    ~BackfillSender() override;
    BackfillSender(const BackfillSender&) = delete;
    BackfillSender& operator=(const BackfillSender&) = delete;

    /// Starts reading the log; stop() (or the destructor) ends it. The topic's samples are numbered `topic`.
    void start(core::TopicId topic);
    void stop();

    std::optional<core::Sample> next_when_idle(base::SteadyTime now) override;
    std::optional<base::SteadyTime> next_ready(base::SteadyTime now) const override;

    /// The sample of row `row_id` that this sender handed out left for the link, `payload_bytes` serialized: the
    /// row waits for the camp's acknowledgement.
    void left(std::int64_t row_id, std::size_t payload_bytes);
    /// The sample of row `row_id` that this sender handed out never reached the link: the row may go again at once.
    void not_left(std::int64_t row_id);
    /// The base camp stored the rows `ranges` (first and last row ids, both included) of the log `log_id`. Those of
    /// another log (another robot's, or this robot's before its log was made anew) are not this sender's.
    void acknowledged(const std::array<std::uint8_t, 16>& log_id,
                      const std::vector<std::pair<std::int64_t, std::int64_t>>& ranges);

    /// Every row not acknowledged (core::BackfillPlanner::Backlog).
    core::BackfillPlanner::Backlog backlog() const;
    struct Counts {
        std::uint64_t sent = 0;          ///< samples that left, resends included
        std::uint64_t acknowledged = 0;  ///< rows the camp acknowledged, of those this sender knew
        std::uint64_t not_sent = 0;      ///< samples handed out that never reached the link
    };
    Counts counts() const;
    const std::array<std::uint8_t, 16>& log_id() const { return log_id_; }

  private:
    void run();
    /// Reads rows added to the log since the last page into the planner.
    void read_new_rows();
    /// Reads ahead what the planner says goes next, while there is room; true when a sample became ready.
    bool read_ahead(base::SteadyTime now);

    log::RobotLog& log_;
    const Config config_;
    const core::WireModel wire_;
    const base::Clock& clock_;
    const std::function<void()> wake_loop_;
    const std::array<std::uint8_t, 16> log_id_;
    core::TopicId topic_ = 0;

    mutable std::mutex mutex_;
    std::condition_variable wake_;
    core::BackfillPlanner planner_;   // under mutex_
    std::deque<core::Sample> ready_;  // under mutex_
    Counts counts_;                   // under mutex_
    bool told_none_ = false;          // under mutex_: next_when_idle found ready_ empty since the last wake
    bool refill_ = false;             // under mutex_: the loop took a sample, there is room to read ahead
    bool stopping_ = false;           // under mutex_
    std::int64_t read_up_to_ = 0;     // the reading thread's: the last row id paged in
    std::thread thread_;
};

}  // namespace tgw::dds
