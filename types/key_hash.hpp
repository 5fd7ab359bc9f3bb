// The RTPS key hash of a keyed sample, from its payload and its type's IDL: what a writer that sends none
// (Cyclone DDS by default) leaves the gateway to work out, so that its history keeps every instance apart.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <utility>

#include "types/type_library.hpp"

namespace tgw::types {

using KeyHash = std::array<std::uint8_t, 16>;

/// Computes key hashes for one struct type (DDS-RTPS 2.3, 9.6.3.8): the key members in declaration order (a
/// base's first), serialized big endian in the payload's CDR version (XCDR1: 8-byte members aligned to 8; XCDR2:
/// to 4), alignment counted from the key's first byte. A member of struct type contributes that struct's key
/// members, or all its members when it declares none. When the key can never take more than 16 bytes it is the
/// hash, zero-padded; otherwise (a string or a sequence among the keys, as Cyclone DDS decides it) the hash is
/// the MD5 of it. Cyclone DDS computes it so when told to send it (GenerateKeyhash); Fast DDS's generated types
/// differ for a key member of struct type (they serialize the whole struct), but Fast DDS writers send their own.
class KeyHasher {
  public:
    /// The hasher for `type_name` (as DDS names it: "tgw_xv::KeyedBlob"), or nullopt with the reason in `why`:
    /// unknown, not a struct, no @key member, or a key of a type the decoder cannot read.
    static std::optional<KeyHasher> for_type(const TypeLibrary& types, const std::string& type_name, std::string& why);

    /// The key hash of one sample (`size` bytes, the encapsulation header first); nullopt when the payload does
    /// not decode as the type, with the decoder's reason in `why`.
    std::optional<KeyHash> hash(const std::uint8_t* data, std::size_t size, std::string& why) const;

  private:
    KeyHasher(const TypeLibrary& types, std::string type_name, std::size_t decoded_members, bool md5_xcdr1,
              bool md5_xcdr2)
        : types_(&types),
          type_name_(std::move(type_name)),
          decoded_members_(decoded_members),
          md5_xcdr1_(md5_xcdr1),
          md5_xcdr2_(md5_xcdr2) {}

    const TypeLibrary* types_;
    std::string type_name_;
    std::size_t decoded_members_;  ///< the members up to the last key's: what follows is never read
    bool md5_xcdr1_;               ///< the XCDR1 key may take more than 16 bytes
    bool md5_xcdr2_;               ///< the XCDR2 key may
};

}  // namespace tgw::types
