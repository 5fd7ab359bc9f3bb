#include "sensor/guarded_sensor.hpp"

#include <cctype>
#include <cmath>
#include <sstream>
#include <utility>

#include "base/config_error.hpp"

namespace tgw::sensor {

namespace {

/// Errors that differ only in their numbers ("backlog 12 B" / "backlog 14 B") are the same kind of failure.
std::string kind_of(const std::string& error) {
    std::string kind;
    for (const char c : error) {
        if (std::isdigit(static_cast<unsigned char>(c))) {
            if (kind.empty() || kind.back() != '#')
                kind += '#';
        } else {
            kind += c;
        }
    }
    return kind;
}

std::string bps_text(double rate_bps) {
    return std::to_string(static_cast<long long>(std::llround(rate_bps))) + " bit/s";
}

std::string seconds_text(base::Duration d) {
    std::ostringstream out;
    out.precision(3);
    out << base::to_seconds(d) << " s";
    return out.str();
}

}  // namespace

std::string GuardConfig::validate() const {
    if (hold < base::Duration::zero())
        return "hold must not be negative";
    if (!std::isfinite(floor_bps) || floor_bps < 0.0)
        return "floor_bps must be a rate >= 0 bit/s";
    if (!(smoothing > 0.0 && smoothing <= 1.0))
        return "smoothing must be in (0, 1]";
    if (!(margin >= 0.0 && margin < 1.0))
        return "margin must be in [0, 1)";
    return {};
}

GuardedSensor::GuardedSensor(std::unique_ptr<RateSensor> inner, GuardConfig config, const base::Clock& clock,
                             SensorLog log)
    : inner_(std::move(inner)), config_(config), clock_(clock), log_(std::move(log)) {
    if (!inner_)
        throw base::ConfigError("guarded sensor: no sensor to guard");
    if (auto error = config_.validate(); !error.empty())
        throw base::ConfigError("sensor " + inner_->describe() + ": " + error);
}

void GuardedSensor::log(SensorLogLevel level, const std::string& message) const {
    if (log_)
        log_(level, "sensor " + inner_->describe() + ": " + message);
}

void GuardedSensor::failure_ended(base::SteadyTime now) {
    if (failure_.empty())
        return;
    log(SensorLogLevel::info, "failure ended after " + seconds_text(now - failure_start_) + ": " + failure_);
    failure_.clear();
    failure_kind_.clear();
}

RateReading GuardedSensor::fallback(const std::string& error, base::SteadyTime now) {
    const std::string kind = kind_of(error);
    const bool new_episode = kind != failure_kind_;
    if (new_episode) {
        failure_ended(now);
        failure_ = error;
        failure_kind_ = kind;
        failure_start_ = now;
    }
    const bool can_hold = last_good_ && smoothed_bps_ && now - *last_good_ <= config_.hold;
    const GuardState next = can_hold ? GuardState::holding : GuardState::floor;
    if (new_episode) {
        if (next == GuardState::holding) {
            log(SensorLogLevel::warning, "reading failed: " + error + "; holding the last good rate for up to " +
                                             seconds_text(config_.hold - (now - *last_good_)));
        } else {
            log(SensorLogLevel::warning,
                "reading failed: " + error + "; using the floor rate " + bps_text(config_.floor_bps));
        }
    } else if (next == GuardState::floor && state_ == GuardState::holding) {
        log(SensorLogLevel::warning, "no good reading for " + seconds_text(now - *last_good_) +
                                         "; using the floor rate " + bps_text(config_.floor_bps));
    }
    state_ = next;

    RateReading reading;
    reading.ok = true;
    if (state_ == GuardState::holding) {
        reading.rate_bps = *smoothed_bps_ * (1.0 - config_.margin);
        reading.detail = "holding last good (" + error + ")";
    } else {
        reading.rate_bps = config_.floor_bps;
        reading.detail = "floor (" + error + ")";
        smoothed_bps_.reset();  // a reading after the floor starts the average afresh
    }
    return reading;
}

RateReading GuardedSensor::read() {
    const base::SteadyTime now = clock_.now();
    RateReading raw = inner_->read();
    if (raw.ok && !(std::isfinite(raw.rate_bps) && raw.rate_bps >= 0.0)) {
        raw.ok = false;
        raw.error = "the sensor read an invalid rate " + std::to_string(raw.rate_bps);
    }
    if (!raw.ok)
        return fallback(raw.error.empty() ? "reading failed without a reason" : raw.error, now);

    failure_ended(now);
    state_ = GuardState::tracking;
    last_good_ = now;
    if (!smoothed_bps_ || raw.rate_bps <= *smoothed_bps_)
        smoothed_bps_ = raw.rate_bps;
    else
        smoothed_bps_ = *smoothed_bps_ + config_.smoothing * (raw.rate_bps - *smoothed_bps_);

    RateReading reading = std::move(raw);
    const double sensed_bps = reading.rate_bps;
    reading.rate_bps = *smoothed_bps_ * (1.0 - config_.margin);
    if (reading.rate_bps != sensed_bps)
        reading.detail += std::string(reading.detail.empty() ? "" : ", ") + "sensed " + bps_text(sensed_bps);
    return reading;
}

std::string GuardedSensor::describe() const {
    return inner_->describe();
}

}  // namespace tgw::sensor
