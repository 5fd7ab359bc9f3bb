// An MCAP file (https://mcap.dev/spec, major version 0) as Foxglove, rosbag2 and the MCAP libraries read it:
// messages in chunks, each chunk followed by its message indexes, and a summary section (schemas, channels,
// statistics, chunk indexes) with its offsets, so that a reader finds any time range without reading the data.
#pragma once

#include <cstdint>
#include <cstdio>
#include <map>
#include <string>
#include <vector>

namespace tgw::basecamp {

/// How chunks are compressed.
enum class McapCompression { none, zstd, lz4 };

/// "none", "zstd" or "lz4" as McapCompression; throws base::ConfigError naming `flag` otherwise.
McapCompression parse_mcap_compression(const std::string& text, const std::string& flag);

class McapWriter {
  public:
    /// Creates `path` and writes its header. Throws base::ConfigError naming `flag` and the file if it cannot.
    McapWriter(const std::string& path, const std::string& flag, McapCompression compression = McapCompression::none,
               std::size_t chunk_bytes = 1 << 20);
    /// Closes the file as close() does, if it was not closed.
    ~McapWriter();
    McapWriter(const McapWriter&) = delete;
    McapWriter& operator=(const McapWriter&) = delete;

    /// A schema: its id (from 1). `encoding` "omgidl" for IDL text, `name` the fully scoped type name.
    std::uint16_t add_schema(const std::string& name, const std::string& encoding, const std::string& data);
    /// A channel: its id (from 0). `schema_id` 0 is a channel without schema.
    std::uint16_t add_channel(std::uint16_t schema_id, const std::string& topic, const std::string& message_encoding,
                              const std::map<std::string, std::string>& metadata = {});
    /// One message; times in nanoseconds since the Unix epoch. The sequence number counts per channel.
    void write_message(std::uint16_t channel_id, std::uint64_t log_time, std::uint64_t publish_time,
                       const std::uint8_t* data, std::size_t size);

    /// Writes the last chunk, the summary and the footer, and closes the file. False when a write failed (the
    /// file is then incomplete, as after a crash: its chunks are still readable in order).
    bool close();

    std::uint64_t messages() const { return message_count_; }

  private:
    struct Schema {
        std::uint16_t id;
        std::string name, encoding, data;
    };
    struct Channel {
        std::uint16_t id, schema_id;
        std::string topic, message_encoding;
        std::map<std::string, std::string> metadata;
        std::uint32_t next_sequence = 0;
    };
    struct ChunkIndex {
        std::uint64_t start_time, end_time, chunk_offset, chunk_length;
        std::map<std::uint16_t, std::uint64_t> message_index_offsets;
        std::uint64_t message_index_length, compressed_size, uncompressed_size;
        std::string compression;
    };

    void write_chunk();
    /// Appends to the file and to the CRC of what the file holds so far.
    void write(const std::vector<std::uint8_t>& bytes);

    std::FILE* file_ = nullptr;
    const std::string path_;
    const McapCompression compression_;
    const std::size_t chunk_bytes_;
    bool failed_ = false;
    std::uint64_t offset_ = 0;
    std::uint32_t crc_ = 0;

    std::vector<Schema> schemas_;
    std::vector<Channel> channels_;
    std::vector<ChunkIndex> chunk_indexes_;
    std::map<std::uint16_t, std::uint64_t> channel_message_counts_;
    std::uint64_t message_count_ = 0;
    std::uint64_t start_time_ = 0, end_time_ = 0;

    // The chunk being filled: its records, and per channel (log time, offset in the records) of its messages.
    std::vector<std::uint8_t> chunk_;
    std::map<std::uint16_t, std::vector<std::pair<std::uint64_t, std::uint64_t>>> chunk_index_;
    std::uint64_t chunk_start_ = 0, chunk_end_ = 0;
};

}  // namespace tgw::basecamp
