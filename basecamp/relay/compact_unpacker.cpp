#include "basecamp/relay/compact_unpacker.hpp"

#include <algorithm>
#include <cstdio>
#include <functional>
#include <iterator>

#include <fastdds/dds/domain/DomainParticipant.hpp>
#include <fastdds/dds/publisher/DataWriter.hpp>
#include <fastdds/dds/publisher/Publisher.hpp>
#include <fastdds/dds/subscriber/DataReader.hpp>
#include <fastdds/dds/subscriber/DataReaderListener.hpp>
#include <fastdds/dds/subscriber/SampleInfo.hpp>
#include <fastdds/dds/subscriber/Subscriber.hpp>
#include <fastdds/dds/topic/Topic.hpp>

#include "CompactWanPubSubTypes.h"
#include "base/config_error.hpp"
#include "basecamp/capture/backfill_archive.hpp"
#include "basecamp/capture/wan_capture.hpp"
#include "basecamp/channel/channel_grantor.hpp"
#include "compact/zstd_frame.hpp"
#include "passthrough/dds_time.hpp"
#include "passthrough/guarded_type.hpp"
#include "passthrough/offered_qos.hpp"
#include "passthrough/passthrough_qos.hpp"
#include "passthrough/passthrough_type.hpp"
#include "passthrough/take_each.hpp"
#include "passthrough/writer_match_counter.hpp"
#include "wire/backfill_codec.hpp"
#include "wire/backfill_topics.hpp"
#include "wire/compact_topics.hpp"
#include "wire/status_topic.hpp"

namespace tgw::basecamp {

namespace fdds = eprosima::fastdds::dds;

namespace {

// How long an entry of a topic no catalog entry described yet may wait for one, whatever its TTL.
constexpr auto CATALOG_WAIT = std::chrono::seconds(10);
// A bundle's DDS sample beyond its bytes: the encapsulation header and the sequence's length.
constexpr std::size_t BUNDLE_ENVELOPE_BYTES = 8;
// Room for the bursts between two listener calls.
constexpr std::int32_t BUNDLE_READER_DEPTH = 256;

std::optional<base::Duration> duration_or_infinite(std::int64_t ns) {
    if (ns < 0)
        return std::nullopt;
    return std::chrono::duration_cast<base::Duration>(std::chrono::nanoseconds(ns));
}

passthrough::OfferedQos offered_qos(const wan::LaneOffer& lane) {
    passthrough::OfferedQos offer;
    offer.reliable = lane.reliable();
    offer.transient_local = lane.transient_local();
    offer.partitions = lane.partitions();
    std::sort(offer.partitions.begin(), offer.partitions.end());
    offer.deadline = duration_or_infinite(lane.deadline_ns());
    offer.liveliness = static_cast<passthrough::OfferedQos::Liveliness>(std::min<std::uint8_t>(lane.liveliness(), 2));
    offer.liveliness_lease = duration_or_infinite(lane.liveliness_lease_ns());
    offer.exclusive_ownership = lane.exclusive_ownership();
    offer.ownership_strength = lane.ownership_strength();
    offer.xcdr2 = lane.xcdr2();
    return offer;
}

}  // namespace

/// One lane of a gateway's topic: the local writer that offers what the lane's robot publishers offered.
struct CompactUnpacker::LocalLane {
    ~LocalLane() {
        if (writer != nullptr) {
            const_cast<fdds::Publisher*>(writer->get_publisher())->delete_datawriter(writer);
        }
    }
    fdds::DataWriter* writer = nullptr;
    passthrough::WriterMatchCounter matches;
    std::uint64_t relayed = 0;  // under mutex_
};

/// One topic of one gateway, as its catalog entry describes it.
struct CompactUnpacker::Stream {
    wan::CatalogEntry entry;
    TopicRecord record;
    std::vector<std::unique_ptr<LocalLane>> lanes;  ///< by lane index; null until poll() makes it
};

namespace {

/// Takes every sample of `Data` its reader has and hands each valid one to `on_sample`, in the taking thread.
template <typename Data>
class TakingListener final : public fdds::DataReaderListener {
  public:
    explicit TakingListener(std::function<void(Data&, const fdds::SampleInfo&)> on_sample)
        : on_sample_(std::move(on_sample)) {}
    void on_data_available(fdds::DataReader* reader) override { passthrough::take_valid<Data>(*reader, on_sample_); }

  private:
    std::function<void(Data&, const fdds::SampleInfo&)> on_sample_;
};

}  // namespace

CompactUnpacker::CompactUnpacker(fdds::DomainParticipant* wan, fdds::DomainParticipant* local,
                                 passthrough::PartitionGroups<fdds::Publisher>& publishers, DeliveryTally& tally,
                                 SampleConsumer* store, ChannelGrantor* statuses, BackfillArchive* backfill)
    : wan_(wan),
      local_(local),
      publishers_(publishers),
      tally_(tally),
      store_(store),
      statuses_(statuses),
      backfill_(backfill),
      catalog_listener_(std::make_unique<TakingListener<wan::CatalogEntry>>(
          [this](wan::CatalogEntry& entry, const fdds::SampleInfo& info) {
              on_catalog(writer_prefix(info), std::move(entry));
          })),
      bundle_listener_(
          std::make_unique<TakingListener<wan::Bundle>>([this](wan::Bundle& bundle, const fdds::SampleInfo& info) {
              // The bundle's DDS sample: its encapsulation and length, then the bytes.
              tally_.add(writer_guid(info), info.sample_identity.sequence_number().to64long(),
                         BUNDLE_ENVELOPE_BYTES + bundle.bytes().size());
              compact::Bundle decoded;
              const compact::BundleError error =
                  compact::BundleCodec::decode(bundle.bytes().data(), bundle.bytes().size(), decoded);
              const std::int64_t received_ns = receive_ns(info);
              // How long the channel took: from the write time the bundle holds (its DDS message has no
              // timestamp, dds::UnstampedWrite), or from its DDS source timestamp (a gateway before 2026-11-28).
              const std::optional<base::Duration> one_way =
                  decoded.write_ns
                      ? std::optional<base::Duration>(std::chrono::nanoseconds(received_ns - *decoded.write_ns))
                      : one_way_delay(info);
              if (one_way && statuses_ != nullptr)
                  statuses_->arrived(writer_prefix(info), *one_way, BUNDLE_ENVELOPE_BYTES + bundle.bytes().size());
              on_bundle(writer_prefix(info), error, decoded, bundle.bytes().size(), received_ns);
          })) {
    fdds::TypeSupport catalog_type(new passthrough::GuardedType<wan::CatalogEntryPubSubType>());
    fdds::TypeSupport bundle_type(new passthrough::GuardedType<wan::BundlePubSubType>());
    fdds::Subscriber* subscriber = wan_->create_subscriber(fdds::SUBSCRIBER_QOS_DEFAULT);
    if (subscriber == nullptr || catalog_type.register_type(wan_) != ReturnCode_t::RETCODE_OK ||
        bundle_type.register_type(wan_) != ReturnCode_t::RETCODE_OK) {
        throw base::ConfigError("--domain: cannot subscribe to the compact WAN mode's topics");
    }
    fdds::Topic* catalog_topic =
        wan_->create_topic(wire::COMPACT_CATALOG_TOPIC, catalog_type.get_type_name(), fdds::TOPIC_QOS_DEFAULT);
    fdds::Topic* bundle_topic =
        wan_->create_topic(wire::COMPACT_BUNDLE_TOPIC, bundle_type.get_type_name(), fdds::TOPIC_QOS_DEFAULT);

    // The catalog: reliable and transient-local, so that every entry the gateways wrote reaches a late joiner.
    fdds::DataReaderQos catalog_qos = subscriber->get_default_datareader_qos();
    catalog_qos.reliability().kind = fdds::RELIABLE_RELIABILITY_QOS;
    catalog_qos.durability().kind = fdds::TRANSIENT_LOCAL_DURABILITY_QOS;
    catalog_qos.history().kind = fdds::KEEP_LAST_HISTORY_QOS;
    catalog_qos.history().depth = 1;
    catalog_qos.resource_limits().max_instances = 65536;
    catalog_qos.resource_limits().max_samples_per_instance = 1;
    catalog_qos.resource_limits().max_samples = fdds::LENGTH_UNLIMITED;
    // The bundles: best effort, as the gateway writes them.
    fdds::DataReaderQos bundle_qos = subscriber->get_default_datareader_qos();
    bundle_qos.reliability().kind = fdds::BEST_EFFORT_RELIABILITY_QOS;
    bundle_qos.history().kind = fdds::KEEP_LAST_HISTORY_QOS;
    bundle_qos.history().depth = BUNDLE_READER_DEPTH;

    if (catalog_topic != nullptr && bundle_topic != nullptr) {
        catalog_reader_ = subscriber->create_datareader(catalog_topic, catalog_qos, catalog_listener_.get(),
                                                        fdds::StatusMask::data_available());
        bundle_reader_ = subscriber->create_datareader(bundle_topic, bundle_qos, bundle_listener_.get(),
                                                       fdds::StatusMask::data_available());
    }
    if (catalog_reader_ == nullptr || bundle_reader_ == nullptr) {
        throw base::ConfigError("--domain: cannot subscribe to " + std::string(wire::COMPACT_BUNDLE_TOPIC) + " and " +
                                wire::COMPACT_CATALOG_TOPIC);
    }
}

CompactUnpacker::~CompactUnpacker() {
    // The readers first: no callback may find a writer gone.
    for (fdds::DataReader* reader : {bundle_reader_, catalog_reader_}) {
        if (reader != nullptr) {
            reader->set_listener(nullptr);
            const_cast<fdds::Subscriber*>(reader->get_subscriber())->delete_datareader(reader);
        }
    }
    std::lock_guard<std::mutex> lock(mutex_);
    streams_.clear();
}

void CompactUnpacker::on_catalog(const ParticipantPrefix& gateway, wan::CatalogEntry entry) {
    std::lock_guard<std::mutex> lock(mutex_);
    new_entries_.emplace_back(gateway, std::move(entry));
}

void CompactUnpacker::on_bundle(const ParticipantPrefix& gateway, compact::BundleError error, compact::Bundle& bundle,
                                std::size_t bytes, std::int64_t receive_ns) {
    std::lock_guard<std::mutex> lock(mutex_);
    ++counts_.bundles;
    if (error != compact::BundleError::none) {
        ++counts_.rejected_bundles;
        const auto kind = static_cast<std::size_t>(error) % error_reported_.size();
        if (!error_reported_[kind]) {
            error_reported_[kind] = true;
            std::fprintf(stderr, "tm-basecamp relay: rejected a bundle of %zu bytes from %s: %s (reported once)\n",
                         bytes, prefix_text(gateway).c_str(), compact::to_string(error));
        }
        return;
    }
    // A gap in the sequence is bundles lost on the link; a step back is the gateway starting again.
    auto [next, first] = next_bundle_.try_emplace(gateway, bundle.sequence);
    if (!first && bundle.sequence > next->second) {
        counts_.lost_bundles += bundle.sequence - next->second;
    }
    next->second = bundle.sequence + 1;

    counts_.entries += bundle.entries.size();
    for (compact::BundleEntry& entry : bundle.entries) {
        if (entry.chunked && !reassemble_nts(gateway, entry, receive_ns)) {
            continue;  // more chunks to come
        }
        if (!deliver_nts(gateway, entry, receive_ns)) {
            if (waiting_.size() >= PENDING_LIMIT) {
                ++counts_.unknown_entries;
                continue;
            }
            waiting_.push_back(Waiting{gateway, std::move(entry), receive_ns, base::SteadyClock::now()});
        }
    }
}

bool CompactUnpacker::reassemble_nts(const ParticipantPrefix& gateway, compact::BundleEntry& entry,
                                     std::int64_t receive_ns) {
    const ReassemblyKey key{gateway, entry.topic_id, entry.chunk.sample_id};
    auto it = reassembly_.find(key);
    if (it == reassembly_.end()) {
        if (reassembly_.size() >= REASSEMBLY_LIMIT || entry.chunk.total_bytes > MAX_CHUNKED_SAMPLE_BYTES) {
            ++counts_.incomplete_samples;
            return false;
        }
        Reassembly r;
        r.sample = entry;
        r.sample.chunked = false;
        r.sample.payload.assign(entry.chunk.total_bytes, 0);
        r.since = base::SteadyClock::now();
        it = reassembly_.emplace(key, std::move(r)).first;
    }
    Reassembly& r = it->second;
    // The codec checked that the chunk lies within its total; a total that disagrees is another sample's.
    if (entry.chunk.total_bytes != r.sample.payload.size()) {
        return false;
    }
    std::copy(entry.payload.begin(), entry.payload.end(),
              r.sample.payload.begin() + static_cast<std::ptrdiff_t>(entry.chunk.offset));
    r.received += entry.payload.size();
    r.receive_ns = receive_ns;
    if (r.received < r.sample.payload.size()) {
        return false;
    }
    entry = std::move(r.sample);
    reassembly_.erase(it);
    return true;
}

void CompactUnpacker::archive_backfill_nts(const compact::BundleEntry& entry, std::int64_t receive_ns) {
    const std::optional<idl::BackfillSample> sample =
        entry.kind == compact::EntryKind::data ? wire::decode_backfill(entry.payload) : std::nullopt;
    if (!sample) {
        ++counts_.undecodable_entries;
        return;
    }
    if (backfill_ != nullptr) {
        backfill_->take(*sample, receive_ns);
    }
}

bool CompactUnpacker::deliver_nts(const ParticipantPrefix& gateway, compact::BundleEntry& entry,
                                  std::int64_t receive_ns) {
    const auto it = streams_.find({gateway, entry.topic_id});
    if (it != streams_.end() && it->second->entry.topic() == wire::BACKFILL_TOPIC) {
        archive_backfill_nts(entry, receive_ns);  // past its TTL: the archive's, never the local domain's
        return true;
    }
    if (it == streams_.end() || entry.lane >= it->second->lanes.size() || !it->second->lanes[entry.lane]) {
        return false;
    }
    Stream& stream = *it->second;
    LocalLane& lane = *stream.lanes[entry.lane];
    passthrough::PassthroughData data;
    fdds::InstanceHandle_t handle = fdds::HANDLE_NIL;
    if (stream.entry.keyed()) {
        if (entry.keyed) {
            for (std::size_t i = 0; i < entry.key.size(); ++i) {
                data.key.value[i] = entry.key[i];
            }
        }
        handle = data.key.isDefined() ? data.key : passthrough::PassthroughType::UNKNOWN_INSTANCE;
    }
    const base::WallTime source{
        std::chrono::duration_cast<base::WallTime::duration>(std::chrono::nanoseconds(entry.source_ns))};
    const eprosima::fastrtps::Time_t stamp = passthrough::to_dds_time(source);
    ReturnCode_t rc = ReturnCode_t::RETCODE_OK;
    switch (entry.kind) {
        case compact::EntryKind::data: {
            // The gateway's status travels compressed: as published again, recorded and granted from, it is the
            // serialized status; the grantor sizes the robot's floor by what it took on the WAN.
            const std::size_t sent_bytes = entry.payload.size();
            if (stream.entry.zstd_payload()) {
                std::vector<std::uint8_t> raw;
                if (compact::unzstd_frame(entry.payload.data(), entry.payload.size(),
                                          compact::BundleCodec::MAX_DECODED_BYTES, raw) != compact::FrameError::none) {
                    if (counts_.undecodable_entries++ == 0) {
                        std::fprintf(stderr,
                                     "tm-basecamp relay: an entry of '%s' is not the zstd frame its catalog "
                                     "entry promised: dropped (counted at exit)\n",
                                     stream.entry.topic().c_str());
                    }
                    return true;
                }
                entry.payload = std::move(raw);
            }
            if (store_ != nullptr) {
                SampleRecord record;
                record.topic = stream.record.topic;
                record.type_name = stream.record.type_name;
                record.payload = entry.payload;
                record.source_ns = entry.source_ns;
                record.receive_ns = receive_ns;
                record.lifespan_ns = stream.record.lifespan_ns;
                if (stream.entry.keyed())
                    record.instance.assign(entry.key.begin(), entry.key.end());
                store_->add(std::move(record));
            }
            if (statuses_ != nullptr && stream.record.topic == wire::STATUS_TOPIC) {
                statuses_->take_status(entry.payload, sent_bytes);
            }
            data.payload = std::move(entry.payload);
            rc = lane.writer->write_w_timestamp(&data, handle, stamp);
            break;
        }
        case compact::EntryKind::dispose:
            rc = lane.writer->dispose_w_timestamp(&data, handle, stamp);
            break;
        case compact::EntryKind::unregister:
            rc = lane.writer->unregister_instance_w_timestamp(&data, handle, stamp);
            break;
    }
    if (rc == ReturnCode_t::RETCODE_OK) {
        ++lane.relayed;
        ++counts_.relayed;
    } else if (counts_.failed_writes++ == 0) {
        std::fprintf(stderr, "tm-basecamp relay: a local write on '%s' failed (code %d)\n",
                     stream.entry.topic().c_str(), static_cast<int>(rc()));
    }
    return true;
}

void CompactUnpacker::poll() {
    std::deque<std::pair<ParticipantPrefix, wan::CatalogEntry>> entries;
    {
        std::lock_guard<std::mutex> lock(mutex_);
        entries.swap(new_entries_);
    }
    for (auto& [gateway, entry] : entries) {
        const std::pair<ParticipantPrefix, std::uint32_t> key{gateway, entry.topic_id()};
        Stream* stream = nullptr;
        std::size_t lanes_made = 0;
        {
            std::lock_guard<std::mutex> lock(mutex_);
            auto& slot = streams_[key];
            if (!slot) {
                slot = std::make_unique<Stream>();
            }
            stream = slot.get();
            lanes_made = stream->lanes.size();
            stream->entry = entry;
        }
        if (entry.topic() == wire::BACKFILL_TOPIC) {
            continue;  // no local writer: its samples go into the archive (archive_backfill_nts)
        }
        // Streams are only added, and only this thread adds lanes: `stream` stays valid, and its lanes past
        // lanes_made are this thread's to make.
        TopicRecord record;
        record.topic = entry.topic();
        record.type_name = entry.type_name();
        record.keyed = entry.keyed();
        record.discovered_ns = base::to_ns(base::WallClock::now());
        fdds::Topic* topic = passthrough::passthrough_topic(local_, entry.topic(), entry.type_name(), entry.keyed());
        for (std::size_t i = 0; i < entry.lanes().size(); ++i) {
            const wan::LaneOffer& offer = entry.lanes()[i];
            const auto lifespan = duration_or_infinite(offer.lifespan_ns());
            if (i == 0) {
                record.reliable = offer.reliable();
                if (lifespan)
                    record.lifespan_ns = lifespan->count();
            }
            if (i < lanes_made && stream->lanes[i]) {
                continue;
            }
            const passthrough::OfferedQos qos = offered_qos(offer);
            fdds::Publisher* publisher = publishers_.get(local_, qos);
            auto lane = std::make_unique<LocalLane>();
            if (topic != nullptr && publisher != nullptr) {
                lane->writer = publisher->create_datawriter(
                    topic,
                    passthrough::passthrough_writer_qos(publisher->get_default_datawriter_qos(), qos, entry.keyed(),
                                                        lifespan),
                    &lane->matches, fdds::StatusMask::publication_matched());
            }
            if (lane->writer == nullptr) {
                std::fprintf(stderr, "tm-basecamp relay: cannot republish '%s' (type '%s', %s)\n",
                             entry.topic().c_str(), entry.type_name().c_str(), qos.describe().c_str());
                continue;
            }
            std::lock_guard<std::mutex> lock(mutex_);
            if (stream->lanes.size() <= i) {
                stream->lanes.resize(i + 1);
            }
            stream->lanes[i] = std::move(lane);
        }
        const bool first = lanes_made == 0;
        {
            std::lock_guard<std::mutex> lock(mutex_);
            stream->record = record;
        }
        if (first && store_ != nullptr) {
            store_->add_topic(record);
        }
    }

    // What waited for these writers goes now; what waited too long goes nowhere, counted.
    std::lock_guard<std::mutex> lock(mutex_);
    const base::SteadyTime now = base::SteadyClock::now();
    std::deque<Waiting> still;
    for (Waiting& w : waiting_) {
        if (deliver_nts(w.gateway, w.entry, w.receive_ns)) {
            continue;
        }
        const auto it = streams_.find({w.gateway, w.entry.topic_id});
        const base::Duration patience =
            it != streams_.end() ? std::chrono::duration_cast<base::Duration>(
                                       std::chrono::nanoseconds(std::max<std::int64_t>(it->second->entry.ttl_ns(), 0)))
                                 : std::chrono::duration_cast<base::Duration>(CATALOG_WAIT);
        if (now - w.since > patience) {
            ++counts_.unknown_entries;
            continue;
        }
        still.push_back(std::move(w));
    }
    waiting_.swap(still);
    for (auto it = reassembly_.begin(); it != reassembly_.end();) {
        if (now - it->second.since > CATALOG_WAIT) {
            ++counts_.incomplete_samples;
            it = reassembly_.erase(it);
        } else {
            ++it;
        }
    }
}

CompactUnpacker::Counts CompactUnpacker::counts() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return counts_;
}

std::map<std::string, std::uint64_t> CompactUnpacker::relayed() const {
    std::lock_guard<std::mutex> lock(mutex_);
    std::map<std::string, std::uint64_t> out;
    for (const auto& [key, stream] : streams_) {
        if (stream->entry.topic() == wire::BACKFILL_TOPIC)
            continue;  // archived, never relayed
        std::uint64_t& n = out[stream->entry.topic()];
        for (const auto& lane : stream->lanes) {
            n += lane ? lane->relayed : 0;
        }
    }
    return out;
}

std::int32_t CompactUnpacker::local_readers(const std::string& topic) const {
    std::lock_guard<std::mutex> lock(mutex_);
    std::int32_t n = 0;
    for (const auto& [key, stream] : streams_) {
        if (stream->entry.topic() != topic)
            continue;
        for (const auto& lane : stream->lanes) {
            n += lane ? lane->matches.matched.load() : 0;
        }
    }
    return n;
}

}  // namespace tgw::basecamp
