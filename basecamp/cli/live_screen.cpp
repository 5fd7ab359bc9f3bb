#include "basecamp/cli/live_screen.hpp"

#include <unistd.h>

#include <chrono>
#include <iostream>

#include "basecamp/cli/subcommand.hpp"

namespace tgw::basecamp {

void run_live_screen(base::Duration duration, const std::function<void(base::Duration)>& step,
                     const std::function<void(std::ostream&)>& draw) {
    const bool terminal = isatty(STDOUT_FILENO) != 0;
    const auto end = duration > base::Duration::zero() ? base::SteadyClock::now() + duration : base::SteadyTime::max();
    while (!stop_requested().load() && base::SteadyClock::now() < end) {
        step(std::chrono::seconds(1));
        if (terminal) {
            std::cout << "\x1b[H\x1b[2J";  // one screen, redrawn
        }
        draw(std::cout);
        std::cout << (terminal ? "" : "\n") << std::flush;
    }
}

}  // namespace tgw::basecamp
