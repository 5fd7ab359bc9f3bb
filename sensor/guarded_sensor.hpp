#pragma once

#include <functional>
#include <memory>
#include <optional>
#include <string>

#include "base/clock.hpp"
#include "sensor/rate_sensor.hpp"

namespace tgw::sensor {

/// How GuardedSensor rides out a sensor's trouble and how cautiously it passes readings on.
struct GuardConfig {
    /// How long after the last good reading its value still stands in for failed ones. A few polls: long enough
    /// to ride out a lost netlink reply or an access point's roam, short enough not to trust a stale rate.
    base::Duration hold = std::chrono::seconds(10);
    /// The rate used once the hold is over (or before any good reading), in bit/s. 10 kbit/s is the bottom of
    /// the paper's range: enough for the shortest-TTL topics of its workload. Set it to what the radio always
    /// carries.
    double floor_bps = 10'000.0;
    /// Weight of a new reading in the exponential average when the rate rises, in (0, 1]; 1 = no smoothing.
    /// A falling rate is followed at once: sending more than the link carries is the costly mistake.
    double smoothing = 0.5;
    /// Fraction taken off the smoothed rate, in [0, 1): headroom for what the sensor cannot see (retries,
    /// another sender on the channel, a shaper's rounding).
    double margin = 0.05;

    /// "" when usable, else what is wrong, naming the field.
    std::string validate() const;
};

/// Where GuardedSensor's rate comes from now.
enum class GuardState {
    tracking,  ///< the sensor's own readings
    holding,   ///< the sensor fails; the last good value stands in
    floor,     ///< the sensor has failed for longer than the hold, or never read: the floor rate
};

enum class SensorLogLevel { info, warning };
/// Receives GuardedSensor's messages: one when a kind of failure starts, one when it ends, never one per poll.
using SensorLog = std::function<void(SensorLogLevel, const std::string&)>;

/// Wraps any sensor so that the gateway always has a rate to budget with: a failed reading keeps the last good
/// value for `hold`, then falls back to `floor_bps`; good readings are smoothed on the way up and reduced by the
/// margin. Failures of the same kind (the same error with its numbers left out) are one episode: logged when it
/// starts and when it ends. Pure logic: time comes from the injected clock. Not thread-safe.
class GuardedSensor final : public RateSensor {
  public:
    /// `clock` must outlive the sensor; `log` may be empty. Throws base::ConfigError when `config` is invalid.
    GuardedSensor(std::unique_ptr<RateSensor> inner, GuardConfig config, const base::Clock& clock, SensorLog log);

    /// Always ok, with a rate >= 0. `detail` is the inner sensor's, plus what the guard did ("holding ...",
    /// "floor ...") and why; queued_bytes is passed on from a good reading.
    RateReading read() override;
    /// The inner sensor's SPEC.
    std::string describe() const override;

    GuardState state() const { return state_; }

  private:
    void log(SensorLogLevel level, const std::string& message) const;
    void failure_ended(base::SteadyTime now);
    RateReading fallback(const std::string& error, base::SteadyTime now);

    std::unique_ptr<RateSensor> inner_;
    GuardConfig config_;
    const base::Clock& clock_;
    SensorLog log_;

    GuardState state_ = GuardState::floor;
    std::optional<double> smoothed_bps_;  ///< before the margin
    std::optional<base::SteadyTime> last_good_;
    std::string failure_;       ///< the error of the current failure episode, "" when none
    std::string failure_kind_;  ///< failure_ with its digits left out
    base::SteadyTime failure_start_{};
};

/// make_sensor(spec, clock) wrapped in a GuardedSensor: what the gateway uses for `--sensor SPEC` with a guard.
/// Throws base::ConfigError as make_sensor does, or naming the field of an invalid `config`.
std::unique_ptr<RateSensor> make_guarded_sensor(const std::string& spec, const GuardConfig& config,
                                                const base::Clock& clock, SensorLog log);

}  // namespace tgw::sensor
