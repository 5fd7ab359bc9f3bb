// tm-basecamp relay's side of the compact WAN mode: bundles in, each sample on its own topic again.
#pragma once

#include <array>
#include <atomic>
#include <cstdint>
#include <deque>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <tuple>
#include <vector>

#include "CompactWan.h"
#include "base/time.hpp"
#include "basecamp/capture/delivery_tally.hpp"
#include "basecamp/sample/sample_consumer.hpp"
#include "compact/bundle_codec.hpp"
#include "passthrough/partition_groups.hpp"

namespace eprosima::fastdds::dds {
class DataReader;
class DataReaderListener;
class DataWriter;
class DomainParticipant;
class Publisher;
class Subscriber;
}  // namespace eprosima::fastdds::dds

namespace tgw::basecamp {

class ChannelGrantor;

/// Reads the catalog and the bundles of every compact-mode gateway on the WAN domain and writes each entry on the
/// local domain as the sample it was: its topic and type name, its instance and source timestamp, through a writer
/// that offers what its robot publisher offered, with the gateway's Lifespan (the TTL), so it expires here when it
/// would have there. A bundle that does not decode (compact::BundleError) is counted, reported once, and dropped;
/// nothing in it is trusted. A sample that came in chunks is put together and passed on whole once its last chunk
/// is in; one whose chunks stop coming is dropped, counted, after CATALOG_WAIT. Entries of a topic whose catalog entry
/// has not arrived yet wait for it, up to their TTL (at most PENDING_LIMIT of them); a base camp that joins late
/// decodes as soon as the catalog reaches it.
///
/// Local writers are made in poll(), from the thread that runs the relay, never in a DDS callback.
class BackfillArchive;

class CompactUnpacker {
  public:
    struct Counts {
        std::uint64_t bundles = 0;
        std::uint64_t entries = 0;
        std::uint64_t relayed = 0;
        std::uint64_t rejected_bundles = 0;
        std::uint64_t lost_bundles = 0;     ///< gaps in a gateway's bundle sequence
        std::uint64_t unknown_entries = 0;  ///< never described by a catalog entry in time
        std::uint64_t failed_writes = 0;
        std::uint64_t incomplete_samples = 0;   ///< chunks of a sample whose other chunks never came
        std::uint64_t undecodable_entries = 0;  ///< of a compressed topic (zstd_payload), not one good zstd frame
    };

    /// Entries waiting for their catalog entry, at most.
    static constexpr std::size_t PENDING_LIMIT = 4096;
    /// Samples being put together from their chunks at once, at most, and the largest one.
    static constexpr std::size_t REASSEMBLY_LIMIT = 64;
    static constexpr std::uint32_t MAX_CHUNKED_SAMPLE_BYTES = 16u << 20;

    /// Reads on `wan`, writes on `local` through `publishers`' groups; all must outlive it. Every bundle taken is
    /// counted in `tally` against its writer, as a sample is in standard mode: the receiver reports then tell the
    /// gateway what became of its bundles. `store`: where the relay records, or nullptr; `statuses`: the grantor
    /// that reads the gateways' statuses (relay --channel-rate), or nullptr; `backfill`: where the gateways'
    /// backfilled samples go (never onto the local domain), or nullptr to drop them. Throws base::ConfigError when
    /// DDS refuses a reader.
    CompactUnpacker(eprosima::fastdds::dds::DomainParticipant* wan, eprosima::fastdds::dds::DomainParticipant* local,
                    passthrough::PartitionGroups<eprosima::fastdds::dds::Publisher>& publishers, DeliveryTally& tally,
                    SampleConsumer* store, ChannelGrantor* statuses = nullptr, BackfillArchive* backfill = nullptr);
    ~CompactUnpacker();
    CompactUnpacker(const CompactUnpacker&) = delete;
    CompactUnpacker& operator=(const CompactUnpacker&) = delete;

    /// Makes the local writers of new catalog entries and passes on what waited for them. The relay's thread.
    void poll();

    Counts counts() const;
    /// Samples written on the local domain per topic, and local readers matched per topic.
    std::map<std::string, std::uint64_t> relayed() const;
    std::int32_t local_readers(const std::string& topic) const;

  private:
    struct LocalLane;
    struct Stream;
    struct Waiting {
        ParticipantPrefix gateway;
        compact::BundleEntry entry;
        std::int64_t receive_ns;
        base::SteadyTime since;
    };

    struct Reassembly {
        compact::BundleEntry sample;  ///< the first chunk's description, the payload as long as the whole
        std::size_t received = 0;
        std::int64_t receive_ns = 0;
        base::SteadyTime since;
    };
    using ReassemblyKey = std::tuple<ParticipantPrefix, std::uint32_t, std::uint32_t>;  // gateway, topic, sample

    void on_catalog(const ParticipantPrefix& gateway, wan::CatalogEntry entry);
    /// Adds a chunk; true (and `entry` the whole sample) when it was the last one. mutex_ held.
    bool reassemble_nts(const ParticipantPrefix& gateway, compact::BundleEntry& entry, std::int64_t receive_ns);
    /// A bundle of `bytes` as it decoded (`error`), its entries taken from `bundle`.
    void on_bundle(const ParticipantPrefix& gateway, compact::BundleError error, compact::Bundle& bundle,
                   std::size_t bytes, std::int64_t receive_ns);
    /// A backfilled sample (wire::BACKFILL_TOPIC's entry) into the archive. mutex_ held.
    void archive_backfill_nts(const compact::BundleEntry& entry, std::int64_t receive_ns);
    /// Writes the entry on the local domain if its lane's writer exists; false if it must wait. mutex_ held.
    bool deliver_nts(const ParticipantPrefix& gateway, compact::BundleEntry& entry, std::int64_t receive_ns);

    eprosima::fastdds::dds::DomainParticipant* wan_;
    eprosima::fastdds::dds::DomainParticipant* local_;
    passthrough::PartitionGroups<eprosima::fastdds::dds::Publisher>& publishers_;
    DeliveryTally& tally_;
    SampleConsumer* store_;
    ChannelGrantor* statuses_;   ///< takes the gateways' statuses (tm-basecamp relay --channel-rate), or nullptr
    BackfillArchive* backfill_;  ///< takes the gateways' backfilled samples, or nullptr
    std::unique_ptr<eprosima::fastdds::dds::DataReaderListener> catalog_listener_;
    std::unique_ptr<eprosima::fastdds::dds::DataReaderListener> bundle_listener_;
    eprosima::fastdds::dds::DataReader* catalog_reader_ = nullptr;
    eprosima::fastdds::dds::DataReader* bundle_reader_ = nullptr;

    mutable std::mutex mutex_;
    std::map<std::pair<ParticipantPrefix, std::uint32_t>, std::unique_ptr<Stream>> streams_;
    std::deque<std::pair<ParticipantPrefix, wan::CatalogEntry>> new_entries_;
    std::deque<Waiting> waiting_;
    std::map<ReassemblyKey, Reassembly> reassembly_;
    std::map<ParticipantPrefix, std::uint32_t> next_bundle_;
    Counts counts_;
    std::array<bool, 8> error_reported_{};
};

}  // namespace tgw::basecamp
