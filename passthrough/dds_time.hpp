#pragma once

#include <cstdint>
#include <optional>

#include <fastdds/rtps/common/Time_t.h>

#include "base/time.hpp"

namespace tgw::passthrough {

/// Conversions between Fast DDS times and the core's, at the edge (STYLE: Time).

/// A QoS duration (lifespan, lease) as a core Duration; nullopt when infinite or invalid.
inline std::optional<base::Duration> to_duration(const eprosima::fastrtps::Duration_t& d) {
    if (d == eprosima::fastrtps::c_TimeInfinite || d.seconds < 0) {
        return std::nullopt;
    }
    return std::chrono::seconds(d.seconds) + std::chrono::nanoseconds(d.nanosec);
}

inline eprosima::fastrtps::Duration_t to_dds_duration(base::Duration d) {
    const std::int64_t ns = d.count();
    return eprosima::fastrtps::Duration_t(static_cast<std::int32_t>(ns / 1'000'000'000),
                                          static_cast<std::uint32_t>(ns % 1'000'000'000));
}

/// A source timestamp as wall time; nullopt when the writer sent none.
inline std::optional<base::WallTime> to_wall_time(const eprosima::fastrtps::rtps::Time_t& t) {
    if (t.seconds() <= 0 && t.nanosec() == 0) {
        return std::nullopt;
    }
    if (t == eprosima::fastrtps::rtps::c_RTPSTimeInvalid || t == eprosima::fastrtps::rtps::c_RTPSTimeInfinite) {
        return std::nullopt;
    }
    return base::wall_from_ns(t.to_ns());
}

inline eprosima::fastrtps::Time_t to_dds_time(base::WallTime t) {
    const std::int64_t ns = base::to_ns(t);
    return eprosima::fastrtps::Time_t(static_cast<std::int32_t>(ns / 1'000'000'000),
                                      static_cast<std::uint32_t>(ns % 1'000'000'000));
}

}  // namespace tgw::passthrough
