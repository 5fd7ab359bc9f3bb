// The gateway reads receiver reports off the WAN, where any participant can write: any bytes either decode to a
// report or are refused (never an exception out of the type support, which Fast DDS would not catch), and any
// sequence of reports from any receivers keeps the ledger's figures sane: in flight never above what was
// forwarded, nothing wrapped, and the delivered-rate check's budget a finite rate within the sensor's claim.
// An input is a sequence of records: [receiver and time step][forwarded delta, 4 bytes LE][length][payload].
#include <cmath>
#include <cstring>
#include <string>

#include "ReceiverReportPubSubTypes.h"
#include "passthrough/guarded_type.hpp"
#include "sensor/delivered_rate_estimator.hpp"
#include "sensor/receiver_report_ledger.hpp"
#include "sensor/receiver_report_source.hpp"
#include "test/fakes/fake_clock.hpp"
#include "test/fuzz/fuzz_target.hpp"

namespace tgw::fuzz {

constexpr double CLAIMED_BPS = 20'000;

namespace {

std::string serialized(std::uint64_t received, std::uint64_t bytes, std::uint64_t lost) {
    idl::ReceiverReportPubSubType type;
    idl::ReceiverReport report;
    report.gateway_prefix().fill(7);
    report.received_samples(received);
    report.received_bytes(bytes);
    report.lost_samples(lost);
    report.sent_ns(1'700'000'000'000'000'000ULL);
    eprosima::fastrtps::rtps::SerializedPayload_t payload(type.m_typeSize);
    type.serialize(&report, &payload);
    return std::string(reinterpret_cast<const char*>(payload.data), payload.length);
}

std::string record(std::uint8_t receiver_and_step, std::uint32_t forwarded_delta, const std::string& payload) {
    std::string r(1, static_cast<char>(receiver_and_step));
    for (int i = 0; i < 4; ++i)
        r.push_back(static_cast<char>(forwarded_delta >> (8 * i)));
    r.push_back(static_cast<char>(payload.size()));
    return r + payload;
}

}  // namespace

std::vector<std::string> seeds() {
    return {
        record(0x04, 100, serialized(0, 0, 0)) + record(0x04, 50, serialized(140, 9'000, 2)) +
            record(0x05, 0, serialized(1, 66, 0)) + record(0xff, 10, serialized(3, 200, 0)),
        record(0x08, 4'000'000'000u, serialized(~0ULL, ~0ULL, ~0ULL)) + record(0x08, 1, serialized(5, 5, 5)),
        record(0x00, 1, serialized(1, 41, 0)),
    };
}

}  // namespace tgw::fuzz

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    using namespace tgw;
    test::FakeClock clock;
    sensor::ReceiverReportLedger ledger(clock, std::chrono::seconds(5));
    sensor::DeliveredRateEstimator estimator({}, clock);
    passthrough::GuardedType<idl::ReceiverReportPubSubType> type;
    std::uint64_t forwarded = 0;
    std::uint64_t sent_bytes = 0;

    std::size_t at = 0;
    while (at + 6 <= size) {
        const std::uint8_t receiver_and_step = data[at];
        std::uint32_t delta = 0;
        for (int i = 0; i < 4; ++i)
            delta |= std::uint32_t{data[at + 1 + i]} << (8 * i);
        const std::size_t length = std::min<std::size_t>(data[at + 5], size - at - 6);
        at += 6;
        eprosima::fastrtps::rtps::SerializedPayload_t payload(static_cast<std::uint32_t>(length));
        if (length > 0)
            std::memcpy(payload.data, data + at, length);
        payload.length = static_cast<std::uint32_t>(length);
        at += length;

        clock.advance(std::chrono::milliseconds(250) * (receiver_and_step >> 2));
        forwarded += delta;
        sent_bytes += std::uint64_t{delta} * 100;
        idl::ReceiverReport report;
        if (!type.deserialize(&payload, &report))
            continue;

        sensor::ReceiverId from{};
        from[0] = receiver_and_step & 0x3;
        const sensor::ReceiverReportCounts counts{report.received_samples(), report.received_bytes(),
                                                  report.lost_samples()};
        if (ledger.take(from, counts, forwarded)) {
            const auto totals = ledger.latest();
            TGW_FUZZ_CHECK(totals.has_value());
            TGW_FUZZ_CHECK(totals->received_samples == counts.received_samples);
            TGW_FUZZ_CHECK(totals->reports >= 1);
            TGW_FUZZ_CHECK(totals->in_flight_samples <= forwarded);
        }
        const auto totals = ledger.latest();
        if (!totals)
            continue;
        const sensor::ReceiverCounts wire = sensor::receiver_counts(*totals, 174, 300);
        TGW_FUZZ_CHECK(wire.received_wire_bytes >= totals->received_bytes);
        TGW_FUZZ_CHECK(wire.in_flight_bytes >= totals->in_flight_samples);
        const sensor::CounterSource source =
            sensor::with_receiver_reports({}, [&wire] { return std::optional<sensor::ReceiverCounts>(wire); });
        const sensor::KernelCountersReading reading = source();
        TGW_FUZZ_CHECK(reading.ok);
        const sensor::LinkCounters counters{sent_bytes, reading.counters.tx_bytes, reading.counters.drops,
                                            reading.counters.backlog_bytes};
        const double budget = estimator.update(counters, fuzz::CLAIMED_BPS);
        TGW_FUZZ_CHECK(std::isfinite(budget) && budget >= 0 && budget <= fuzz::CLAIMED_BPS);
    }
    return 0;
}
