#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "base/time.hpp"

namespace tgw::robot_sim {

/// When each periodic stream publishes next. Stream i of n starts i/n of its period after `start`, so the
/// streams do not all fire at once; due times are computed from the start, so they never drift.
class PublishSchedule {
  public:
    PublishSchedule(base::SteadyTime start, const std::vector<double>& rates_hz);

    struct Due {
        std::size_t stream = 0;
        base::SteadyTime at{};
        std::uint32_t sequence = 0;  ///< how many samples of this stream came before
    };

    /// The earliest due publication (the lowest stream index among equals).
    Due next() const;
    /// Marks the publication returned by next() as done.
    void advance();

  private:
    base::SteadyTime due_at(std::size_t stream) const;

    base::SteadyTime start_;
    std::vector<base::Duration> periods_;
    std::vector<base::Duration> phases_;
    std::vector<std::uint32_t> counts_;
};

}  // namespace tgw::robot_sim
