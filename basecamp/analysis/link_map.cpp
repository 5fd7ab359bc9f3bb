#include "basecamp/analysis/link_map.hpp"

#include <algorithm>
#include <cmath>
#include <map>

#include "base/config_error.hpp"
#include "basecamp/status/gateway_status.hpp"
#include "types/cdr_decoder.hpp"
#include "wire/status_topic.hpp"

namespace tgw::basecamp {

namespace {

constexpr char DROPPED_PREFIX[] = "dropped/";  // RecordingReader's channels of a mission archive's drops
constexpr double DROP_CELLS = 40;

/// The number at `path` ("pose.position.x") in a decoded struct; nullopt when there is none.
std::optional<double> number_at(const types::DecodedValue& value, const std::string& path) {
    const types::DecodedValue* at = &value;
    std::size_t start = 0;
    while (start <= path.size()) {
        const std::size_t dot = path.find('.', start);
        const std::string name = path.substr(start, dot == std::string::npos ? std::string::npos : dot - start);
        const auto field = std::find_if(at->fields.begin(), at->fields.end(),
                                        [&](const auto& member) { return member.first == name; });
        if (at->kind != types::DecodedValue::Kind::record || field == at->fields.end())
            return std::nullopt;
        at = &field->second;
        if (dot == std::string::npos)
            break;
        start = dot + 1;
    }
    switch (at->kind) {
        case types::DecodedValue::Kind::real:
            return at->real;
        case types::DecodedValue::Kind::signed_integer:
            return static_cast<double>(at->signed_integer);
        case types::DecodedValue::Kind::unsigned_integer:
            return static_cast<double>(at->unsigned_integer);
        default:
            return std::nullopt;
    }
}

/// Where the robot was at `time_ns`, between the poses around it; the first or last pose outside them.
MapPoint pose_at(const std::vector<MapPoint>& poses, std::int64_t time_ns) {
    const auto after = std::lower_bound(poses.begin(), poses.end(), time_ns,
                                        [](const MapPoint& p, std::int64_t t) { return p.time_ns < t; });
    if (after == poses.begin())
        return poses.front();
    if (after == poses.end())
        return poses.back();
    const MapPoint& a = *(after - 1);
    const MapPoint& b = *after;
    const double f = b.time_ns == a.time_ns
                         ? 0.0
                         : static_cast<double>(time_ns - a.time_ns) / static_cast<double>(b.time_ns - a.time_ns);
    return {time_ns, a.x + f * (b.x - a.x), a.y + f * (b.y - a.y)};
}

}  // namespace

PoseSource PoseSource::parse(const std::string& text, const std::string& flag) {
    PoseSource source;
    const std::size_t colon = text.rfind(':');
    source.topic = text.substr(0, colon);
    if (colon != std::string::npos) {
        const std::string fields = text.substr(colon + 1);
        const std::size_t comma = fields.find(',');
        if (comma == std::string::npos || comma == 0 || comma + 1 == fields.size() ||
            fields.find(',', comma + 1) != std::string::npos)
            throw base::ConfigError(flag + ": expected TOPIC or TOPIC:FIELD_X,FIELD_Y, not '" + text + "'");
        source.field_x = fields.substr(0, comma);
        source.field_y = fields.substr(comma + 1);
    }
    if (source.topic.empty())
        throw base::ConfigError(flag + ": no topic in '" + text + "'");
    return source;
}

LinkMapBuilder::LinkMapBuilder(PoseSource pose, types::TypeLibrary types)
    : pose_(std::move(pose)), types_(std::move(types)) {}

void LinkMapBuilder::add_topic(TopicRecord /*topic*/) {}

void LinkMapBuilder::add_logged_rate(std::int64_t time_ns, double rate_bps) {
    std::lock_guard<std::mutex> lock(mutex_);
    logged_rates_.push_back({time_ns, rate_bps, 0});
}

void LinkMapBuilder::add(SampleRecord sample) {
    if (sample.backfill) {  // dropped on the robot, and in the archive by backfill: a drop all the same
        std::lock_guard<std::mutex> lock(mutex_);
        archive_drops_.push_back({sample.source_ns});
    }
    if (sample.topic == pose_.topic) {
        const types::CdrDecodeResult decoded =
            types::decode_cdr(sample.payload.data(), sample.payload.size(), sample.type_name, types_);
        std::optional<double> x, y;
        if (decoded.value) {
            x = number_at(*decoded.value, pose_.field_x);
            y = number_at(*decoded.value, pose_.field_y);
        }
        std::lock_guard<std::mutex> lock(mutex_);
        ++pose_samples_;
        if (x && y) {
            poses_.push_back({sample.source_ns, *x, *y});
        } else if (pose_error_.empty()) {
            pose_error_ = !decoded.value ? decoded.error
                                         : "a " + sample.type_name + " has no number '" +
                                               (x ? pose_.field_y : pose_.field_x) + "'";
        }
    } else if (sample.topic == wire::STATUS_TOPIC) {
        const auto status = decode_gateway_status(sample.payload);
        if (!status)
            return;
        std::uint64_t logged = 0;
        for (const auto& topic : status->topics())
            logged += logged_on_robot(topic);
        std::lock_guard<std::mutex> lock(mutex_);
        statuses_.push_back({sample.source_ns, status->sensed_rate_bps(), logged});
    } else if (sample.topic.rfind(DROPPED_PREFIX, 0) == 0) {
        std::lock_guard<std::mutex> lock(mutex_);
        archive_drops_.push_back({sample.source_ns});
    }
}

LinkMap LinkMapBuilder::build(const std::string& pose_flag, const std::string& file) const {
    std::lock_guard<std::mutex> lock(mutex_);
    if (poses_.size() < 2) {  // (before the duplicates go: an error message counts what the files held)
        throw base::ConfigError(pose_flag + ": " +
                                (pose_samples_ == 0
                                     ? "no sample of '" + pose_.topic + "' in " + file
                                     : std::to_string(poses_.size()) + " of " + std::to_string(pose_samples_) +
                                           " samples of '" + pose_.topic + "' gave a pose" +
                                           (pose_error_.empty() ? "" : ": " + pose_error_)));
    }
    if (statuses_.empty() && logged_rates_.empty()) {
        throw base::ConfigError(file + ": no " + std::string(wire::STATUS_TOPIC) +
                                " sample to colour the path with (the gateway's --status-period must be above 0)");
    }
    std::vector<MapPoint> poses = poses_;
    std::sort(poses.begin(), poses.end(), [](const MapPoint& a, const MapPoint& b) { return a.time_ns < b.time_ns; });
    // A recording and the mission archive made from it hold the same poses.
    poses.erase(std::unique(poses.begin(), poses.end(),
                            [](const MapPoint& a, const MapPoint& b) { return a.time_ns == b.time_ns; }),
                poses.end());
    std::vector<Status> statuses = statuses_;
    std::sort(statuses.begin(), statuses.end(), [](const Status& a, const Status& b) { return a.time_ns < b.time_ns; });
    statuses.erase(std::unique(statuses.begin(), statuses.end(),
                               [](const Status& a, const Status& b) { return a.time_ns == b.time_ns; }),
                   statuses.end());

    LinkMap map;
    map.poses = poses.size();
    // The gateway's own log of its rate where there is one: statuses leave out what a weak link could not carry.
    std::vector<Status> rates = logged_rates_.empty() ? statuses : logged_rates_;
    std::sort(rates.begin(), rates.end(), [](const Status& a, const Status& b) { return a.time_ns < b.time_ns; });
    map.rates_from = logged_rates_.empty() ? "the gateway's status" : "the gateway's log";
    map.rate_points = rates.size();
    const auto [lowest, highest] = std::minmax_element(
        rates.begin(), rates.end(), [](const Status& a, const Status& b) { return a.rate_bps < b.rate_bps; });
    map.min_rate_bps = lowest->rate_bps;
    map.max_rate_bps = highest->rate_bps;
    for (std::size_t i = 1; i < poses.size(); ++i) {
        MapSegment segment{poses[i - 1], poses[i], std::nullopt};
        const auto after = std::upper_bound(rates.begin(), rates.end(), segment.from.time_ns,
                                            [](std::int64_t t, const Status& s) { return t < s.time_ns; });
        if (after != rates.begin())
            segment.rate_bps = (after - 1)->rate_bps;
        map.segments.push_back(segment);
    }

    // Drops grouped by place: one mark per cell of a grid over the path (DROP_CELLS across its extent), at the
    // mean of its drops, sized by how many. Hundreds of drops would otherwise hide the path.
    double min_x = poses.front().x, max_x = min_x, min_y = poses.front().y, max_y = min_y;
    for (const MapPoint& p : poses) {
        min_x = std::min(min_x, p.x), max_x = std::max(max_x, p.x);
        min_y = std::min(min_y, p.y), max_y = std::max(max_y, p.y);
    }
    const double cell = std::max({max_x - min_x, max_y - min_y, 1e-9}) / DROP_CELLS;
    std::map<std::pair<long, long>, DropMark> marks;
    const auto mark = [&](std::int64_t time_ns, std::uint64_t samples) {
        const MapPoint at = pose_at(poses, time_ns);
        DropMark& m =
            marks[{std::lround(std::floor((at.x - min_x) / cell)), std::lround(std::floor((at.y - min_y) / cell))}];
        const double weight = static_cast<double>(samples) / static_cast<double>(m.samples + samples);
        m.x += (at.x - m.x) * weight;
        m.y += (at.y - m.y) * weight;
        m.samples += samples;
        map.dropped_samples += samples;
    };
    if (!archive_drops_.empty()) {
        map.drops_from = "the mission archive";
        for (const Drop& drop : archive_drops_)
            mark(drop.time_ns, 1);
    } else {
        map.drops_from = "the gateway's status counts";
        for (std::size_t i = 1; i < statuses.size(); ++i) {
            if (statuses[i].logged > statuses[i - 1].logged)
                mark(statuses[i].time_ns, statuses[i].logged - statuses[i - 1].logged);
        }
    }
    for (auto& [index, m] : marks)
        map.drops.push_back(m);
    return map;
}

}  // namespace tgw::basecamp
