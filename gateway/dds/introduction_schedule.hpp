// When the WAN participant should announce itself again to a base camp that has not answered it yet.
#pragma once

#include <array>
#include <cstdint>
#include <map>
#include <optional>

#include "base/time.hpp"

namespace tgw::dds {

/// A participant that joins the WAN domain (a base camp that starts, or restarts after a crash) announces itself
/// to the gateway, and Fast DDS answers it with one announcement of the gateway's own. On a busy slow link that
/// one datagram can be lost in the shaper's queue, and the next periodic announcement comes only
/// WanConfig::announcement_period (20 s) later: until then the base camp ignores everything the gateway sends
/// it, and the robot's samples reach no one.
///
/// This keeps, for each such participant, when to announce again: AFTER[0], AFTER[1], ... after its discovery,
/// until one of its endpoints is announced to us (which it does only once it has discovered us) or it leaves.
/// Pure: the WanRouter's introducer thread asks it what is due and does the announcing.
class IntroductionSchedule {
  public:
    using Prefix = std::array<std::uint8_t, 12>;

    /// Times after a participant's discovery to announce again, while it has not answered.
    static constexpr std::array<base::Duration, 3> AFTER = {std::chrono::seconds(1), std::chrono::seconds(2),
                                                            std::chrono::seconds(4)};

    /// `participant` was discovered at `now`: it may not have heard of us.
    void discovered(const Prefix& participant, base::SteadyTime now);
    /// One of `participant`'s endpoints was announced to us: it knows us.
    void answered(const Prefix& participant);
    /// `participant` left, or its lease ran out.
    void removed(const Prefix& participant);

    /// True if an announcement is due at `now`; each participant it was due for moves on to its next time.
    bool take_due(base::SteadyTime now);
    /// The earliest time an announcement will be due; nullopt when nobody waits for one.
    std::optional<base::SteadyTime> next_due() const;

    /// Participants not yet answered that will still be announced to.
    std::size_t waiting() const { return waiting_.size(); }

  private:
    struct Waiting {
        base::SteadyTime discovered_at;
        std::size_t sent = 0;  ///< announcements of AFTER already due
    };
    std::map<Prefix, Waiting> waiting_;
};

}  // namespace tgw::dds
