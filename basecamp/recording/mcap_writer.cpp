#include "basecamp/recording/mcap_writer.hpp"

#include <cerrno>
#include <cstring>
#include <limits>

#include <lz4frame.h>
#include <zlib.h>
#include <zstd.h>

#include "base/config_error.hpp"

namespace tgw::basecamp {

namespace {

constexpr std::uint8_t MAGIC[] = {0x89, 'M', 'C', 'A', 'P', '0', '\r', '\n'};
constexpr int ZSTD_LEVEL = 3;  // zstd's default: most of the ratio at a fraction of the cost of higher levels

// Record opcodes (spec, "Records").
enum Opcode : std::uint8_t {
    HEADER = 0x01,
    FOOTER = 0x02,
    SCHEMA = 0x03,
    CHANNEL = 0x04,
    MESSAGE = 0x05,
    CHUNK = 0x06,
    MESSAGE_INDEX = 0x07,
    CHUNK_INDEX = 0x08,
    STATISTICS = 0x0B,
    SUMMARY_OFFSET = 0x0E,
    DATA_END = 0x0F,
};

/// A record's content in the spec's little-endian encoding.
class Content {
  public:
    Content& u8(std::uint8_t v) { return raw(&v, 1); }
    Content& u16(std::uint16_t v) { return little_endian(v, 2); }
    Content& u32(std::uint32_t v) { return little_endian(v, 4); }
    Content& u64(std::uint64_t v) { return little_endian(v, 8); }
    Content& string(const std::string& s) {
        u32(static_cast<std::uint32_t>(s.size()));
        return raw(s.data(), s.size());
    }
    Content& raw(const void* data, std::size_t size) {
        const auto* p = static_cast<const std::uint8_t*>(data);
        bytes.insert(bytes.end(), p, p + size);
        return *this;
    }
    /// A map or array: its content, preceded by its length in bytes.
    Content& prefixed32(const Content& inner) {
        u32(static_cast<std::uint32_t>(inner.bytes.size()));
        return raw(inner.bytes.data(), inner.bytes.size());
    }

    std::vector<std::uint8_t> bytes;

  private:
    Content& little_endian(std::uint64_t v, int n) {
        for (int i = 0; i < n; ++i)
            bytes.push_back(static_cast<std::uint8_t>(v >> (8 * i)));
        return *this;
    }
};

/// opcode, content length, content.
std::vector<std::uint8_t> record(Opcode opcode, const Content& content) {
    Content out;
    out.u8(opcode).u64(content.bytes.size()).raw(content.bytes.data(), content.bytes.size());
    return out.bytes;
}

const char* compression_name(McapCompression compression) {
    switch (compression) {
        case McapCompression::zstd:
            return "zstd";
        case McapCompression::lz4:
            return "lz4";
        case McapCompression::none:
            break;
    }
    return "";
}

std::vector<std::uint8_t> compress(McapCompression compression, const std::vector<std::uint8_t>& in) {
    std::vector<std::uint8_t> out;
    if (compression == McapCompression::zstd) {
        out.resize(ZSTD_compressBound(in.size()));
        const std::size_t n = ZSTD_compress(out.data(), out.size(), in.data(), in.size(), ZSTD_LEVEL);
        if (ZSTD_isError(n))
            return {};
        out.resize(n);
    } else if (compression == McapCompression::lz4) {
        out.resize(LZ4F_compressFrameBound(in.size(), nullptr));
        const std::size_t n = LZ4F_compressFrame(out.data(), out.size(), in.data(), in.size(), nullptr);
        if (LZ4F_isError(n))
            return {};
        out.resize(n);
    } else {
        out = in;
    }
    return out;
}

Content schema_content(std::uint16_t id, const std::string& name, const std::string& encoding,
                       const std::string& data) {
    Content c;
    c.u16(id).string(name).string(encoding).u32(static_cast<std::uint32_t>(data.size())).raw(data.data(), data.size());
    return c;
}

Content channel_content(std::uint16_t id, std::uint16_t schema_id, const std::string& topic,
                        const std::string& message_encoding, const std::map<std::string, std::string>& metadata) {
    Content entries;
    for (const auto& [key, value] : metadata)
        entries.string(key).string(value);
    Content c;
    c.u16(id).u16(schema_id).string(topic).string(message_encoding).prefixed32(entries);
    return c;
}

}  // namespace

McapCompression parse_mcap_compression(const std::string& text, const std::string& flag) {
    if (text == "none")
        return McapCompression::none;
    if (text == "zstd")
        return McapCompression::zstd;
    if (text == "lz4")
        return McapCompression::lz4;
    throw base::ConfigError(flag + ": expected none, zstd or lz4, not '" + text + "'");
}

McapWriter::McapWriter(const std::string& path, const std::string& flag, McapCompression compression,
                       std::size_t chunk_bytes)
    : path_(path), compression_(compression), chunk_bytes_(chunk_bytes) {
    file_ = std::fopen(path.c_str(), "wb");
    if (file_ == nullptr)
        throw base::ConfigError(flag + ": cannot create '" + path + "': " + std::strerror(errno));
    Content magic;
    write(magic.raw(MAGIC, sizeof MAGIC).bytes);
    Content header;
    header.string("").string("telemetry-gateway tm-basecamp");  // profile: none of the well-known ones
    write(record(HEADER, header));
}

McapWriter::~McapWriter() {
    close();
}

std::uint16_t McapWriter::add_schema(const std::string& name, const std::string& encoding, const std::string& data) {
    const auto id = static_cast<std::uint16_t>(schemas_.size() + 1);
    schemas_.push_back({id, name, encoding, data});
    // In the chunk too, so that a reader going through the file in order meets it before its channels.
    const auto bytes = record(SCHEMA, schema_content(id, name, encoding, data));
    chunk_.insert(chunk_.end(), bytes.begin(), bytes.end());
    return id;
}

std::uint16_t McapWriter::add_channel(std::uint16_t schema_id, const std::string& topic,
                                      const std::string& message_encoding,
                                      const std::map<std::string, std::string>& metadata) {
    const auto id = static_cast<std::uint16_t>(channels_.size());
    channels_.push_back({id, schema_id, topic, message_encoding, metadata});
    const auto bytes = record(CHANNEL, channel_content(id, schema_id, topic, message_encoding, metadata));
    chunk_.insert(chunk_.end(), bytes.begin(), bytes.end());
    return id;
}

void McapWriter::write_message(std::uint16_t channel_id, std::uint64_t log_time, std::uint64_t publish_time,
                               const std::uint8_t* data, std::size_t size) {
    if (file_ == nullptr || channel_id >= channels_.size())
        return;
    Content message;
    message.u16(channel_id).u32(channels_[channel_id].next_sequence++).u64(log_time).u64(publish_time).raw(data, size);
    if (chunk_index_.empty()) {
        chunk_start_ = log_time;
        chunk_end_ = log_time;
    }
    chunk_start_ = std::min(chunk_start_, log_time);
    chunk_end_ = std::max(chunk_end_, log_time);
    chunk_index_[channel_id].emplace_back(log_time, chunk_.size());
    const auto bytes = record(MESSAGE, message);
    chunk_.insert(chunk_.end(), bytes.begin(), bytes.end());

    if (message_count_ == 0) {
        start_time_ = log_time;
        end_time_ = log_time;
    }
    start_time_ = std::min(start_time_, log_time);
    end_time_ = std::max(end_time_, log_time);
    ++message_count_;
    ++channel_message_counts_[channel_id];
    if (chunk_.size() >= chunk_bytes_)
        write_chunk();
}

void McapWriter::write_chunk() {
    if (chunk_.empty())
        return;
    const std::vector<std::uint8_t> compressed = compress(compression_, chunk_);
    const bool stored_plain = compressed.empty() && !chunk_.empty();  // a compressor's failure loses nothing
    const std::vector<std::uint8_t>& records = stored_plain ? chunk_ : compressed;
    Content chunk;
    chunk.u64(chunk_start_).u64(chunk_end_).u64(chunk_.size());
    chunk.u32(static_cast<std::uint32_t>(::crc32(0L, chunk_.data(), static_cast<uInt>(chunk_.size()))));
    chunk.string(stored_plain ? "" : compression_name(compression_));
    chunk.u64(records.size()).raw(records.data(), records.size());

    ChunkIndex index{chunk_start_,
                     chunk_end_,
                     offset_,
                     0,
                     {},
                     0,
                     records.size(),
                     chunk_.size(),
                     stored_plain ? "" : compression_name(compression_)};
    write(record(CHUNK, chunk));
    index.chunk_length = offset_ - index.chunk_offset;
    const std::uint64_t indexes_start = offset_;
    for (const auto& [channel, entries] : chunk_index_) {
        Content list;
        for (const auto& [time, offset] : entries)
            list.u64(time).u64(offset);
        Content message_index;
        message_index.u16(channel).prefixed32(list);
        index.message_index_offsets[channel] = offset_;
        write(record(MESSAGE_INDEX, message_index));
    }
    index.message_index_length = offset_ - indexes_start;
    chunk_indexes_.push_back(std::move(index));
    chunk_.clear();
    chunk_index_.clear();
}

void McapWriter::write(const std::vector<std::uint8_t>& bytes) {
    if (file_ == nullptr || bytes.empty())
        return;
    if (std::fwrite(bytes.data(), 1, bytes.size(), file_) != bytes.size())
        failed_ = true;
    crc_ = static_cast<std::uint32_t>(::crc32(crc_, bytes.data(), static_cast<uInt>(bytes.size())));
    offset_ += bytes.size();
}

bool McapWriter::close() {
    if (file_ == nullptr)
        return !failed_;
    write_chunk();
    Content data_end;
    data_end.u32(crc_);  // every byte of the file before this record
    write(record(DATA_END, data_end));

    // The summary: one group of records per kind, each group's place in the summary offset section.
    const std::uint64_t summary_start = offset_;
    crc_ = 0;  // from here: the summary's CRC, through the footer's offsets
    std::vector<std::tuple<Opcode, std::uint64_t, std::uint64_t>> groups;
    const auto group = [&](Opcode opcode, const auto& write_group) {
        const std::uint64_t start = offset_;
        write_group();
        if (offset_ > start)
            groups.emplace_back(opcode, start, offset_ - start);
    };
    group(SCHEMA, [&] {
        for (const Schema& s : schemas_)
            write(record(SCHEMA, schema_content(s.id, s.name, s.encoding, s.data)));
    });
    group(CHANNEL, [&] {
        for (const Channel& c : channels_)
            write(record(CHANNEL, channel_content(c.id, c.schema_id, c.topic, c.message_encoding, c.metadata)));
    });
    group(STATISTICS, [&] {
        Content counts;
        for (const auto& [channel, count] : channel_message_counts_)
            counts.u16(channel).u64(count);
        Content stats;
        stats.u64(message_count_).u16(static_cast<std::uint16_t>(schemas_.size()));
        stats.u32(static_cast<std::uint32_t>(channels_.size())).u32(0).u32(0);  // no attachments, no metadata
        stats.u32(static_cast<std::uint32_t>(chunk_indexes_.size())).u64(start_time_).u64(end_time_);
        stats.prefixed32(counts);
        write(record(STATISTICS, stats));
    });
    group(CHUNK_INDEX, [&] {
        for (const ChunkIndex& index : chunk_indexes_) {
            Content offsets;
            for (const auto& [channel, offset] : index.message_index_offsets)
                offsets.u16(channel).u64(offset);
            Content c;
            c.u64(index.start_time).u64(index.end_time).u64(index.chunk_offset).u64(index.chunk_length);
            c.prefixed32(offsets).u64(index.message_index_length).string(index.compression);
            c.u64(index.compressed_size).u64(index.uncompressed_size);
            write(record(CHUNK_INDEX, c));
        }
    });
    const std::uint64_t summary_offset_start = offset_;
    for (const auto& [opcode, start, length] : groups) {
        Content offset;
        offset.u8(opcode).u64(start).u64(length);
        write(record(SUMMARY_OFFSET, offset));
    }
    // The footer's CRC covers the summary sections and the footer up to itself.
    Content footer_start;
    footer_start.u8(FOOTER).u64(8 + 8 + 4).u64(summary_start).u64(summary_offset_start);
    write(footer_start.bytes);
    Content footer_crc;
    footer_crc.u32(crc_);
    write(footer_crc.bytes);
    Content magic;
    write(magic.raw(MAGIC, sizeof MAGIC).bytes);

    if (std::fclose(file_) != 0)
        failed_ = true;
    file_ = nullptr;
    return !failed_;
}

}  // namespace tgw::basecamp
