#include <gtest/gtest.h>

#include <sstream>

#include "base/config_error.hpp"
#include "test/fakes/config_error_of.hpp"
#include "types/type_library.hpp"

namespace tgw::test {
namespace {

using types::IdlEnum;
using types::IdlExtensibility;
using types::IdlStruct;
using types::IdlType;
using types::IdlTypedef;
using Kind = types::IdlType::Kind;

class IdlParserTest : public ::testing::Test {
  protected:
    void parse(const std::string& text, const std::string& file = "robot.idl") {
        std::istringstream in(text);
        sut_.add_idl(in, file);
    }

    /// The message of the ConfigError parsing `text` throws; empty when it parses.
    std::string error_of(const std::string& text) {
        return config_error_of([&] {
            types::TypeLibrary fresh;
            std::istringstream in(text);
            fresh.add_idl(in, "bad.idl");
            fresh.check_references();
        });
    }

    const IdlStruct& structure(const std::string& name) const {
        const auto* declared = sut_.find(name);
        EXPECT_NE(declared, nullptr) << name;
        static const IdlStruct none;
        return declared != nullptr && std::holds_alternative<IdlStruct>(*declared) ? std::get<IdlStruct>(*declared)
                                                                                   : none;
    }

    types::TypeLibrary sut_;
};

TEST_F(IdlParserTest, ReadsTheSubsetRoboticsIdlUses) {
    parse(R"idl(// a comment
#include "std_msgs/msg/Header.idl"
#include <builtin_interfaces/msg/Time.idl>
/* a block
   comment */
module geometry_msgs {
  module msg {
    module Pose_Constants {
      const uint8 FRAMES = 3;
      const string NAME = "pose";
      const double SCALE = 1.5;
    };
    typedef double double__9[9];
    @verbatim (language="comment", text="A pose (with a (parenthesis))")
    @topic
    @final
    struct Pose {
      @key @id(1) unsigned long long id;
      @unit(value="m") double position[Pose_Constants::FRAMES][2];
      string<8> frame, child_frame;
      sequence<float, 0x10> weights;
      sequence<sequence<short>> matrix;
      double__9 covariance;
      boolean ok; char c; octet o; int8 a; uint8 b; int16 d; uint16 e; int32 f; uint32 g; int64 h; uint64 i;
      short j; unsigned short k; long l; unsigned long m; long long n;
    };
  };
};)idl");
    const IdlStruct& pose = structure("geometry_msgs::msg::Pose");
    EXPECT_EQ(pose.extensibility, IdlExtensibility::final);
    EXPECT_TRUE(pose.topic);
    ASSERT_EQ(pose.members.size(), 23u);
    EXPECT_TRUE(pose.members[0].key);
    EXPECT_EQ(pose.members[0].id, 1u);
    EXPECT_EQ(pose.members[0].type.kind, Kind::uint64);
    EXPECT_EQ(pose.members[1].type.kind, Kind::array);
    EXPECT_EQ(pose.members[1].type.dimensions, (std::vector<std::uint32_t>{3, 2}));
    EXPECT_EQ(pose.members[1].type.element->kind, Kind::float64);
    EXPECT_EQ(pose.members[2].name, "frame");
    EXPECT_EQ(pose.members[3].name, "child_frame");
    EXPECT_EQ(pose.members[3].type.bound, 8u);
    EXPECT_EQ(pose.members[4].type.bound, 16u);
    EXPECT_EQ(pose.members[5].type.element->kind, Kind::sequence);
    EXPECT_EQ(pose.members[6].type.kind, Kind::named);
    EXPECT_EQ(pose.members[6].type.scope, "geometry_msgs::msg");
    const Kind kinds[] = {Kind::boolean, Kind::char8, Kind::octet,  Kind::int8,  Kind::uint8,  Kind::int16,
                          Kind::uint16,  Kind::int32, Kind::uint32, Kind::int64, Kind::uint64, Kind::int16,
                          Kind::uint16,  Kind::int32, Kind::uint32, Kind::int64};
    for (std::size_t i = 0; i < std::size(kinds); ++i)
        EXPECT_EQ(pose.members[7 + i].type.kind, kinds[i]) << pose.members[7 + i].name;
    const auto* covariance = sut_.find("geometry_msgs::msg::double__9");
    ASSERT_NE(covariance, nullptr);
    EXPECT_EQ(std::get<IdlTypedef>(*covariance).type.dimensions, (std::vector<std::uint32_t>{9}));
    EXPECT_EQ(sut_.constant("Pose_Constants::FRAMES", "geometry_msgs::msg"), 3);
    EXPECT_NO_THROW(sut_.check_references());
}

TEST_F(IdlParserTest, ReadsEnumsInheritanceAndExtensibility) {
    parse(R"(
      module m {
        @bit_bound(8) enum Mode { IDLE, @value(10) RUN, STOP };
        @appendable struct Base { long id; };
        @extensibility(MUTABLE) struct Derived : Base { Mode mode; @optional long extra; };
        struct Later : ::m::Base { };
      };)");
    const auto* mode = sut_.find("m::Mode");
    ASSERT_NE(mode, nullptr);
    const IdlEnum& enumeration = std::get<IdlEnum>(*mode);
    EXPECT_EQ(enumeration.bit_bound, 8u);
    ASSERT_EQ(enumeration.enumerators.size(), 3u);
    EXPECT_EQ(enumeration.enumerators[2].name, "STOP");
    EXPECT_EQ(enumeration.enumerators[2].value, 11);
    EXPECT_EQ(structure("m::Base").extensibility, IdlExtensibility::appendable);
    const IdlStruct& derived = structure("m::Derived");
    EXPECT_EQ(derived.extensibility, IdlExtensibility::mutable_);
    ASSERT_TRUE(derived.base.has_value());
    EXPECT_EQ(derived.base->name, "Base");
    EXPECT_TRUE(derived.members[1].optional);
    EXPECT_EQ(structure("m::Later").base->name, "::m::Base");
    EXPECT_NO_THROW(sut_.check_references());
}

TEST_F(IdlParserTest, FindsTypesByTheFullyScopedNameDdsAnnouncesAndResolvesNamesOutwards) {
    parse("module std_msgs { module msg { module dds_ { struct String_ { string data; }; }; }; };");
    parse(
        "module a { struct Inner { long x; }; module b { struct Uses { Inner i; b::Deeper d; }; "
        "struct Deeper { long y; }; }; };",
        "a.idl");
    EXPECT_NE(sut_.find("std_msgs::msg::dds_::String_"), nullptr);
    EXPECT_NE(sut_.find("::std_msgs::msg::dds_::String_"), nullptr);
    EXPECT_EQ(sut_.find("String_"), nullptr);
    EXPECT_NE(sut_.resolve("Inner", "a::b"), nullptr);
    EXPECT_EQ(types::declaration_name(*sut_.resolve("b::Deeper", "a::b")), "a::b::Deeper");
    EXPECT_EQ(sut_.resolve("Inner", ""), nullptr);
    EXPECT_NO_THROW(sut_.check_references());
}

TEST_F(IdlParserTest, ParseErrorsNameTheFileAndTheLine) {
    EXPECT_EQ(error_of("module m {\n  struct S {\n    long x\n  };\n};\n"),
              "bad.idl:4: expected ';' after the member, found '}'");
    EXPECT_EQ(error_of("struct S {\n  string<N> s;\n};"),
              "bad.idl:2: the string's bound: 'N' is not an integer constant declared before");
    EXPECT_EQ(error_of("struct S { long a[0]; };"),
              "bad.idl:1: the array's dimension must be between 1 and "
              "4294967295, not 0");
    EXPECT_EQ(error_of("/* never\nclosed"), "bad.idl:1: a comment that never ends (/* without */)");
    EXPECT_EQ(error_of("struct S {\n long a;\n"),
              "bad.idl:3: expected '}' to close struct S, found the end of the file");
    EXPECT_EQ(error_of("interface I { };"),
              "bad.idl:1: expected a declaration (module, struct, enum, typedef, const), found 'interface'");
    EXPECT_EQ(error_of("struct S { long $x; };"), "bad.idl:1: unexpected character '$'");
    EXPECT_EQ(error_of("\n\nstruct S { Missing m; };"), "bad.idl:3: unknown type 'Missing'");
    EXPECT_EQ(error_of("struct S { long a; };\nstruct S { long b; };"),
              "bad.idl:2: S is already declared at bad.idl:1");
    EXPECT_EQ(error_of("const long X = 1 / 0;"), "bad.idl:1: the constant X: division by zero");
    EXPECT_EQ(error_of("struct S { @key(MAYBE) long a; };"), "bad.idl:1: @key takes TRUE or FALSE");
}

TEST_F(IdlParserTest, SkipsUnionsAndKeepsUnsupportedMemberTypesForTheDecoderToRefuse) {
    parse(R"(
      union Choice switch (long) { case 1: long a; default: string b; };
      bitmask Flags { A, B };
      struct S { wstring w; wchar c; long double ld; map<string, long> m; Choice choice; };)");
    const IdlStruct& s = structure("S");
    ASSERT_EQ(s.members.size(), 5u);
    EXPECT_EQ(s.members[0].type.kind, Kind::unsupported);
    EXPECT_EQ(s.members[0].type.name, "wstring");
    EXPECT_EQ(s.members[2].type.name, "long double");
    EXPECT_EQ(s.members[3].type.name, "map");
    ASSERT_NE(sut_.find("Choice"), nullptr);
    EXPECT_EQ(std::get<types::IdlUnsupported>(*sut_.find("Choice")).what, "union");
    EXPECT_NO_THROW(sut_.check_references());
}

}  // namespace
}  // namespace tgw::test
