// The gateway's side of a fleet's shared channel (--channel-grants): the base camp's grant for this gateway.
#pragma once

#include <functional>
#include <mutex>
#include <optional>

#include <fastdds/dds/subscriber/DataReaderListener.hpp>
#include <fastdds/rtps/common/GuidPrefix_t.hpp>

#include "base/clock.hpp"
#include "core/granted_rate.hpp"

namespace tgw::dds {

/// The listener of the gateway's reader of CHANNEL_GRANT_TOPIC: keeps the latest grant for its own WAN participant
/// (`own`) and the newcomers' share (NEWCOMER_PREFIX), and calls `changed` as either comes, in Fast DDS's thread.
/// The gateway joins the channel when the reader is made (core::JOIN_WAIT).
class GrantReader final : public eprosima::fastdds::dds::DataReaderListener {
  public:
    GrantReader(const eprosima::fastrtps::rtps::GuidPrefix_t& own, const base::Clock& clock,
                std::function<void()> changed);

    void on_data_available(eprosima::fastdds::dds::DataReader* reader) override;

    /// Its own grant in bit/s while it is valid; nullopt before the first, and once the last has run out.
    std::optional<double> current() const;
    /// Its own grant and the newcomers' share, each while valid, and whether the gateway is still joining: no grant
    /// of either kind heard yet, within core::JOIN_WAIT.
    core::GrantView view() const;

    /// The gateway's WAN participant was made anew (WanRouter::rebind): grants for `own` are its own from here.
    void set_own(const eprosima::fastrtps::rtps::GuidPrefix_t& own);

    /// Calls `changed` no more: once it returns, what `changed` uses may go while the reader still exists.
    void close();

  private:
    const base::Clock& clock_;
    const std::function<void()> changed_;
    mutable std::mutex mutex_;
    eprosima::fastrtps::rtps::GuidPrefix_t own_;  // under mutex_
    struct Heard {
        std::optional<double> rate_bps;
        base::SteadyTime valid_until{};
        std::optional<double> in_force(base::SteadyTime now) const;
    };
    Heard own_grant_;  // under mutex_
    Heard newcomer_;   // under mutex_
    const base::SteadyTime join_until_;
    std::mutex changed_mutex_;  ///< held while `changed_` runs
    bool closed_ = false;       // under changed_mutex_
};

}  // namespace tgw::dds
