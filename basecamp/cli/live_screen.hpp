#pragma once

#include <functional>
#include <ostream>

#include "base/time.hpp"

namespace tgw::basecamp {

/// The loop of a live tool (stats, status): runs `step(slice)` a second at a time until `duration` has passed
/// (zero: until Ctrl-C) or stop_requested(), and after each second draws `draw` on stdout: in place, one screen,
/// on a terminal; one block after another, a blank line apart, otherwise.
void run_live_screen(base::Duration duration, const std::function<void(base::Duration)>& step,
                     const std::function<void(std::ostream&)>& draw);

}  // namespace tgw::basecamp
