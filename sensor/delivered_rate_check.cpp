#include "sensor/delivered_rate_check.hpp"

#include <cmath>
#include <utility>

#include "base/config_error.hpp"

namespace tgw::sensor {

namespace {

std::string bps_text(double bps) {
    return std::to_string(std::llround(bps)) + " bit/s";
}

const char* verdict_name(LinkVerdict verdict) {
    switch (verdict) {
        case LinkVerdict::unknown:
            return "unknown";
        case LinkVerdict::delivering:
            return "delivering";
        case LinkVerdict::draining:
            return "draining";
        case LinkVerdict::congested:
            return "congested";
    }
    return "?";
}

}  // namespace

DeliveredRateCheck::DeliveredRateCheck(std::unique_ptr<RateSensor> inner, DeliveredRateSources sources,
                                       DeliveredRateConfig config, const base::Clock& clock, SensorLog log)
    : inner_(std::move(inner)), sources_(std::move(sources)), estimator_(config, clock), log_(std::move(log)) {
    if (!sources_.kernel)
        throw base::ConfigError("delivered-rate check: no source of kernel counters");
}

RateReading DeliveredRateCheck::read() {
    RateReading reading = inner_->read();
    if (!reading.ok)
        return reading;
    const KernelCountersReading kernel = sources_.kernel();
    if (!kernel.ok) {
        note_counter_failure(kernel.error);
        return reading;
    }
    note_counter_failure({});

    LinkCounters counters;
    counters.tx_bytes = kernel.counters.tx_bytes;
    counters.drops = kernel.counters.drops;
    counters.backlog_bytes = kernel.counters.backlog_bytes;
    counters.gateway_sent_bytes = sources_.sent_bytes ? sources_.sent_bytes() : kernel.counters.tx_bytes;

    const double claimed_bps = reading.rate_bps;
    reading.rate_bps = estimator_.update(counters, claimed_bps);
    if (!reading.queued_bytes)
        reading.queued_bytes = kernel.counters.backlog_bytes;
    note_cap(claimed_bps);
    reading.cap_bps = estimator_.cap_bps();

    std::string check = "link " + std::string(verdict_name(estimator_.verdict()));
    if (const auto delivered = estimator_.delivered_bps())
        check += ", delivered " + bps_text(*delivered);
    if (const auto cap = estimator_.cap_bps())
        check += ", capped at " + bps_text(*cap);
    reading.detail = reading.detail.empty() ? check : reading.detail + "; " + check;
    return reading;
}

std::string DeliveredRateCheck::describe() const {
    return inner_->describe() + "+delivered-check";
}

void DeliveredRateCheck::log(SensorLogLevel level, const std::string& message) const {
    if (log_)
        log_(level, message);
}

void DeliveredRateCheck::note_counter_failure(const std::string& error) {
    if (error == counter_failure_)
        return;
    if (!counter_failure_.empty() && error.empty())
        // Names what ended: the kernel's counters, or the wait for the base camp's first receiver report.
        log(SensorLogLevel::info,
            "delivered-rate check: over: " + counter_failure_ + "; checking the sensor's rate again");
    if (!error.empty())
        log(SensorLogLevel::warning, "delivered-rate check: " + error + " (passing the sensor's rate through)");
    counter_failure_ = error;
}

void DeliveredRateCheck::note_cap(double claimed_bps) {
    const bool capping = estimator_.cap_bps().has_value();
    if (capping == capping_)
        return;
    capping_ = capping;
    if (capping) {
        log(SensorLogLevel::warning, "delivered-rate check: the link delivers less than the sensor's " +
                                         bps_text(claimed_bps) + " (it drops or queues); budget capped at " +
                                         bps_text(*estimator_.cap_bps()));
    } else {
        log(SensorLogLevel::info, "delivered-rate check: no drops or long queue at up to the sensor's " +
                                      bps_text(claimed_bps) + "; cap lifted");
    }
}

DeliveredRateSources kernel_sources(const std::string& interface, std::function<std::uint64_t()> sent_bytes) {
    auto reader = std::make_shared<LinkCounterReader>(interface);
    DeliveredRateSources sources;
    sources.kernel = [reader] { return reader->read(); };
    sources.sent_bytes = std::move(sent_bytes);
    return sources;
}

}  // namespace tgw::sensor
