// The IDL made from a publisher's XTypes TypeObject decodes the publisher's samples as the IDL file it was
// generated from does. The TypeObjects are those fastddsgen -typeobject generates for test/idl/AnnouncedTypes.idl.
#include <gtest/gtest.h>

#include <fstream>
#include <sstream>

#include <fastrtps/types/TypeObjectFactory.h>

#include "AnnouncedTypes.h"
#include "AnnouncedTypesTypeObject.h"
#include "basecamp/decode/value_json.hpp"
#include "passthrough/type_object_idl.hpp"
#include "test/unit/types/cdr_test_payloads.hpp"
#include "types/cdr_decoder.hpp"
#include "types/type_library.hpp"

namespace tgw::test {
namespace {

namespace xt = eprosima::fastrtps::types;
using passthrough::TypeObjectIdl;

/// Referenced types as a process that registered them knows them.
const xt::TypeObject* registered(const xt::TypeIdentifier& id) {
    return xt::TypeObjectFactory::get_instance()->get_type_object(&id);
}

/// Referenced types as a process that only heard the publisher's discovery data knows them: not at all.
const xt::TypeObject* unknown(const xt::TypeIdentifier&) {
    return nullptr;
}

tgw_test::FlatReading example_reading(std::uint32_t id) {
    tgw_test::FlatReading reading;
    reading.sensor_id(id);
    reading.ok(true);
    reading.grade('B');
    reading.raw(0xA5);
    reading.s16(-12);
    reading.u16(65'000);
    reading.s32(-2'000'000'000);
    reading.s64(-9'000'000'000'000LL);
    reading.u64(18'000'000'000'000'000'000ULL);
    reading.f32(1.5F);
    reading.f64(-273.15);
    reading.label("front \"left\" wheel");
    reading.unit("m/s");
    reading.history({1.0, 2.5, -3.25});
    reading.recent({7, 8});
    reading.grid({{{1, 2, 3}, {4, 5, 6}}});
    return reading;
}

/// The sample as JSON, decoded with `types`; the decoder's error when it cannot.
std::string decoded_json(const std::vector<std::uint8_t>& payload, const std::string& type,
                         const types::TypeLibrary& types) {
    const types::CdrDecodeResult result = types::decode_cdr(payload.data(), payload.size(), type, types);
    if (!result.value)
        return "error: " + result.error;
    std::ostringstream out;
    basecamp::write_json(out, *result.value);
    return out.str();
}

types::TypeLibrary library_of(const std::string& idl, const std::string& file) {
    types::TypeLibrary types;
    std::istringstream in(idl);
    types.add_idl(in, file);
    types.check_references();
    return types;
}

class TypeObjectIdlTest : public ::testing::Test {
  protected:
    static void SetUpTestSuite() { registerAnnouncedTypesTypes(); }

    void SetUp() override {
        std::ifstream in(TGW_TEST_IDL_DIR "/AnnouncedTypes.idl");
        ASSERT_TRUE(in) << TGW_TEST_IDL_DIR "/AnnouncedTypes.idl";
        from_file_ = library_of(std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()),
                                "AnnouncedTypes.idl");
    }

    types::TypeLibrary from_file_;
};

TEST_F(TypeObjectIdlTest, AFlatStructNeedsNothingButItsOwnTypeObject) {
    const TypeObjectIdl idl =
        passthrough::type_object_idl(*tgw_test::GetFlatReadingObject(true), "tgw_test::FlatReading", unknown);
    ASSERT_TRUE(idl.ok()) << idl.missing;
    EXPECT_NE(idl.text.find("@key unsigned long sensor_id;"), std::string::npos) << idl.text;
    EXPECT_NE(idl.text.find("string<16> unit;"), std::string::npos) << idl.text;
    // fastddsgen 2.3 announces it as string<255>; a longer string must decode all the same.
    EXPECT_NE(idl.text.find("string label;"), std::string::npos) << idl.text;
    EXPECT_NE(idl.text.find("sequence<long, 8> recent;"), std::string::npos) << idl.text;
    EXPECT_NE(idl.text.find("long grid[2][3];"), std::string::npos) << idl.text;

    tgw_test::FlatReading reading = example_reading(42);
    reading.label(std::string(300, 'x'));
    const auto payload = fastcdr_payload(reading, eprosima::fastcdr::Cdr::LITTLE_ENDIANNESS);
    const std::string from_type_object =
        decoded_json(payload, "tgw_test::FlatReading", library_of(idl.text, "TypeObject"));
    EXPECT_EQ(from_type_object, decoded_json(payload, "tgw_test::FlatReading", from_file_));
    EXPECT_NE(from_type_object.find("\"sensor_id\":42"), std::string::npos) << from_type_object;
    EXPECT_NE(from_type_object.find("\"grid\":[[1,2,3],[4,5,6]]"), std::string::npos) << from_type_object;
    EXPECT_NE(from_type_object.find("\"label\":\"" + std::string(300, 'x') + "\""), std::string::npos)
        << from_type_object;
}

TEST_F(TypeObjectIdlTest, ReferencedTypesComeFromTheLookupEachDeclaredOnceBeforeItsUse) {
    const TypeObjectIdl idl =
        passthrough::type_object_idl(*tgw_test::GetRoverStateObject(true), "tgw_test::RoverState", registered);
    ASSERT_TRUE(idl.ok()) << idl.missing;
    // FlatReading is declared once, before RoverState. fastddsgen's TypeObjects name the types they
    // refer to without their modules; the announced type has the name its writer announced.
    const auto flat = idl.text.find("struct FlatReading");
    EXPECT_NE(flat, std::string::npos) << idl.text;
    EXPECT_LT(flat, idl.text.find("module tgw_test {\n@appendable\nstruct RoverState {")) << idl.text;
    EXPECT_NE(idl.text.find("@appendable"), std::string::npos) << idl.text;
    EXPECT_NE(idl.text.find("@value(2) RETURNING"), std::string::npos) << idl.text;

    tgw_test::RoverState state;
    state.reading(example_reading(1));
    state.mode(tgw_test::RETURNING);
    state.velocity({0.5, -0.25, 0.0});
    const auto payload = fastcdr_payload(state, eprosima::fastcdr::Cdr::LITTLE_ENDIANNESS);
    const std::string from_type_object =
        decoded_json(payload, "tgw_test::RoverState", library_of(idl.text, "TypeObject"));
    EXPECT_EQ(from_type_object, decoded_json(payload, "tgw_test::RoverState", from_file_));
    EXPECT_NE(from_type_object.find("\"mode\":\"RETURNING\""), std::string::npos) << from_type_object;
    EXPECT_NE(from_type_object.find("\"velocity\":[0.5,-0.25,0.0]"), std::string::npos) << from_type_object;
}

TEST_F(TypeObjectIdlTest, SaysWhichMemberRefersToATypeThePublisherDidNotAnnounce) {
    const TypeObjectIdl idl =
        passthrough::type_object_idl(*tgw_test::GetRoverStateObject(true), "tgw_test::RoverState", unknown);
    EXPECT_FALSE(idl.ok());
    EXPECT_TRUE(idl.text.empty());
    EXPECT_NE(idl.missing.find("member 'reading' of tgw_test::RoverState: refers to a type its publisher did not "
                               "announce (complete hash "),
              std::string::npos)
        << idl.missing;
}

TEST_F(TypeObjectIdlTest, AMinimalTypeObjectNamesNoMembers) {
    const TypeObjectIdl idl =
        passthrough::type_object_idl(*tgw_test::GetFlatReadingObject(false), "tgw_test::FlatReading", registered);
    EXPECT_FALSE(idl.ok());
    EXPECT_NE(idl.missing.find("minimal TypeObject"), std::string::npos) << idl.missing;
}

}  // namespace
}  // namespace tgw::test
