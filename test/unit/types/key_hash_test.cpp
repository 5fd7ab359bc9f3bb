#include <gtest/gtest.h>

#include <fstream>
#include <sstream>
#include <string>

#include <fastdds/rtps/common/InstanceHandle.h>

#include "KeyedReading.h"
#include "KeyedReadingPubSubTypes.h"
#include "KeyedTypes.h"
#include "KeyedTypesPubSubTypes.h"
#include "test/unit/types/cdr_test_payloads.hpp"
#include "types/key_hash.hpp"

namespace tgw::test {
namespace {

using eprosima::fastcdr::Cdr;
using types::KeyHash;
using types::KeyHasher;

class KeyHashTest : public ::testing::Test {
  protected:
    void SetUp() override {
        types_.add_project_types();
        std::ifstream in(TGW_TEST_IDL_DIR "/KeyedTypes.idl");
        ASSERT_TRUE(in) << TGW_TEST_IDL_DIR "/KeyedTypes.idl";
        types_.add_idl(in, "KeyedTypes.idl");
        types_.check_references();
    }

    KeyHasher hasher(const std::string& type_name) {
        std::string why;
        auto made = KeyHasher::for_type(types_, type_name, why);
        EXPECT_TRUE(made) << why;
        return *made;
    }

    KeyHash hash_of(const std::string& type_name, const std::vector<std::uint8_t>& payload) {
        std::string why;
        const auto hash = hasher(type_name).hash(payload.data(), payload.size(), why);
        EXPECT_TRUE(hash) << why;
        return hash.value_or(KeyHash{});
    }

    /// What Fast DDS's generated type support makes of the same sample.
    template <typename PubSubType, typename Sample>
    static KeyHash fast_dds_hash(Sample sample) {
        PubSubType support;
        eprosima::fastrtps::rtps::InstanceHandle_t handle;
        EXPECT_TRUE(support.getKey(&sample, &handle, false));
        KeyHash hash{};
        for (std::size_t i = 0; i < hash.size(); ++i)
            hash[i] = handle.value[i];
        return hash;
    }

    types::TypeLibrary types_;
};

TEST_F(KeyHashTest, AFourByteKeyIsItsBigEndianBytesZeroPadded) {
    tgw::idl::KeyedReading sample;
    sample.sensor_id(0x01020304);
    sample.value(2.5);
    sample.label("left wheel");
    const KeyHash expected = {1, 2, 3, 4, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0};
    for (const auto endianness : {Cdr::LITTLE_ENDIANNESS, Cdr::BIG_ENDIANNESS}) {
        EXPECT_EQ(hash_of("tgw::idl::KeyedReading", fastcdr_payload(sample, endianness)), expected);
    }
    EXPECT_EQ(fast_dds_hash<tgw::idl::KeyedReadingPubSubType>(sample), expected);
}

TEST_F(KeyHashTest, AgreesWithFastDdsGeneratedTypesForEveryKeyShape) {
    tgw_test::PaddedKey padded;
    padded.tag(7);
    padded.serial(-2);
    padded.value(1.0);
    EXPECT_EQ(hash_of("tgw_test::PaddedKey", fastcdr_payload(padded, Cdr::LITTLE_ENDIANNESS)),
              fast_dds_hash<tgw_test::PaddedKeyPubSubType>(padded));

    tgw_test::NamedKey named;
    named.value(3);
    named.name("front-left camera");
    EXPECT_EQ(hash_of("tgw_test::NamedKey", fastcdr_payload(named, Cdr::LITTLE_ENDIANNESS)),
              fast_dds_hash<tgw_test::NamedKeyPubSubType>(named));

    tgw_test::MixedKey mixed;
    mixed.side(tgw_test::RIGHT);
    mixed.slot(9);
    mixed.label("not a key");
    mixed.cell({-1, 65536});
    EXPECT_EQ(hash_of("tgw_test::MixedKey", fastcdr_payload(mixed, Cdr::BIG_ENDIANNESS)),
              fast_dds_hash<tgw_test::MixedKeyPubSubType>(mixed));

    tgw_test::WideKey wide;
    wide.a(1);
    wide.b(2);
    wide.c(3);
    EXPECT_EQ(hash_of("tgw_test::WideKey", fastcdr_payload(wide, Cdr::LITTLE_ENDIANNESS)),
              fast_dds_hash<tgw_test::WideKeyPubSubType>(wide));
}

TEST_F(KeyHashTest, MembersOutsideTheKeyDoNotChangeIt) {
    tgw_test::MixedKey first;
    first.side(tgw_test::LEFT);
    first.slot(1);
    first.label("a");
    first.cell({1, 2});
    tgw_test::MixedKey second = first;
    second.label("a much longer label, which moves nothing of the key");
    EXPECT_EQ(hash_of("tgw_test::MixedKey", fastcdr_payload(first, Cdr::LITTLE_ENDIANNESS)),
              hash_of("tgw_test::MixedKey", fastcdr_payload(second, Cdr::LITTLE_ENDIANNESS)));
    second.slot(2);
    EXPECT_NE(hash_of("tgw_test::MixedKey", fastcdr_payload(first, Cdr::LITTLE_ENDIANNESS)),
              hash_of("tgw_test::MixedKey", fastcdr_payload(second, Cdr::LITTLE_ENDIANNESS)));
}

// XCDR2 aligns an 8-byte member to 4: the key of PaddedKey takes 12 bytes, not 16.
TEST_F(KeyHashTest, AnXcdr2PayloadGivesTheXcdr2Key) {
    const std::vector<std::uint8_t> payload =
        CdrWriter(0x0007, true, true).u8(7).u64(0x1122334455667788).f64(1.0).bytes();
    const KeyHash expected = {7, 0, 0, 0, 0x11, 0x22, 0x33, 0x44, 0x55, 0x66, 0x77, 0x88, 0, 0, 0, 0};
    EXPECT_EQ(hash_of("tgw_test::PaddedKey", payload), expected);
}

// A key member of struct type contributes that struct's keys (DDS-XTypes 1.3, 7.6.8), all its members when it
// has none; a base's keys come first.
TEST_F(KeyHashTest, NestedAndInheritedKeysFollowTheSpecification) {
    std::istringstream idl(R"(
        module nest {
            struct Id { @key octet site; long unused; };
            struct Pair { short a; short b; };
            struct Base { @key unsigned short zone; };
            struct Leaf : Base { @key Id id; @key Pair pair; double value; };
        };)");
    types_.add_idl(idl, "nest.idl");
    const std::vector<std::uint8_t> payload =
        CdrWriter(0x0001, true, false).u16(0x0a0b).u8(5).u32(99).u16(1).u16(2).f64(0.5).bytes();
    // zone 0a0b, site 05, padding to 2, a 0001, b 0002.
    const KeyHash expected = {0x0a, 0x0b, 5, 0, 0, 1, 0, 2, 0, 0, 0, 0, 0, 0, 0, 0};
    EXPECT_EQ(hash_of("nest::Leaf", payload), expected);
}

// The key needs the members up to the last key's only: what follows is never decoded (here it is missing).
TEST_F(KeyHashTest, WhatFollowsTheLastKeyIsNotRead) {
    const std::vector<std::uint8_t> without_value = CdrWriter(0x0001, true, false).u8(7).u64(9).bytes();
    const KeyHash expected = {7, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 9};
    EXPECT_EQ(hash_of("tgw_test::PaddedKey", without_value), expected);
}

TEST_F(KeyHashTest, SaysWhyItCannotHashAType) {
    std::string why;
    EXPECT_FALSE(KeyHasher::for_type(types_, "tgw::idl::RobotPose", why));
    EXPECT_EQ(why, "tgw::idl::RobotPose has no @key member");
    EXPECT_FALSE(KeyHasher::for_type(types_, "nowhere::Thing", why));
    EXPECT_EQ(why, "no IDL for the type nowhere::Thing");
    EXPECT_FALSE(KeyHasher::for_type(types_, "tgw_test::Side", why));
    EXPECT_EQ(why, "tgw_test::Side is not a struct");
}

TEST_F(KeyHashTest, APayloadThatDoesNotDecodeHasNoHash) {
    const std::vector<std::uint8_t> truncated = CdrWriter(0x0001, true, false).u8(7).bytes();
    std::string why;
    EXPECT_FALSE(hasher("tgw_test::PaddedKey").hash(truncated.data(), truncated.size(), why));
    EXPECT_NE(why.find("serial"), std::string::npos) << why;
}

}  // namespace
}  // namespace tgw::test
