#include <gtest/gtest.h>

#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <set>
#include <sstream>

#include "test/fakes/config_error_of.hpp"
#include "types/embedded_idl.hpp"
#include "types/type_library.hpp"

namespace tgw::test {
namespace {

namespace fs = std::filesystem;

std::string read_file(const fs::path& path) {
    std::ifstream in(path, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

class TypeLibraryTest : public ::testing::Test {
  protected:
    void TearDown() override {
        if (!dir_.empty())
            fs::remove_all(dir_);
    }

    /// Writes `text` to `relative` under a directory of this test's own; the directory.
    const fs::path& write(const std::string& relative, const std::string& text) {
        if (dir_.empty()) {
            dir_ = fs::temp_directory_path() / ("tgw_idl_" + std::to_string(::getpid()) + "_" +
                                                ::testing::UnitTest::GetInstance()->current_test_info()->name());
            fs::remove_all(dir_);
        }
        fs::create_directories((dir_ / relative).parent_path());
        std::ofstream(dir_ / relative) << text;
        return dir_;
    }

    void parse(const std::string& text, const std::string& file) {
        std::istringstream in(text);
        sut_.add_idl(in, file);
    }

    types::TypeLibrary sut_;
    fs::path dir_;
};

TEST_F(TypeLibraryTest, ParsesEveryIdlFileOfTheProjectAndEmbedsEachOfThemAsItIs) {
    std::set<std::string> on_disk;
    for (const auto& entry : fs::directory_iterator(TGW_IDL_DIR)) {
        if (entry.path().extension() != ".idl")
            continue;
        on_disk.insert("idl/" + entry.path().filename().string());
        types::TypeLibrary alone;
        std::ifstream in(entry.path());
        EXPECT_NO_THROW(alone.add_idl(in, entry.path().string())) << entry.path();
        EXPECT_NO_THROW(alone.check_references()) << entry.path();
        EXPECT_FALSE(alone.struct_names().empty()) << entry.path();
    }
    std::set<std::string> embedded;
    for (const types::EmbeddedIdl& file : types::embedded_idl_files()) {
        embedded.insert(file.file);
        EXPECT_EQ(file.text, read_file(fs::path(TGW_IDL_DIR) / fs::path(file.file).filename())) << file.file;
    }
    EXPECT_EQ(embedded, on_disk);
}

TEST_F(TypeLibraryTest, KnowsTheProjectTypesWithNoFlag) {
    sut_.add_project_types();
    EXPECT_NO_THROW(sut_.check_references());
    for (const char* name : {"tgw::idl::GatewayStatus", "tgw::idl::TopicStatus", "tgw::idl::KeyedReading",
                             "tgw::idl::PaperMessage", "tgw::idl::ReceiverReport", "std_msgs::msg::dds_::String_"})
        EXPECT_NE(sut_.find(name), nullptr) << name;
}

TEST_F(TypeLibraryTest, LetsAnIdlFileDeclareAProjectTypeAgain) {
    sut_.add_project_types();
    parse("module tgw { module idl { struct KeyedReading { long other; }; }; };", "newer.idl");
    const auto& reading = std::get<types::IdlStruct>(*sut_.find("tgw::idl::KeyedReading"));
    ASSERT_EQ(reading.members.size(), 1u);
    EXPECT_EQ(reading.members[0].name, "other");
}

TEST_F(TypeLibraryTest, ReadsSubdirectoriesAndAnIncludedFileBeforeTheFileThatIncludesIt) {
    write("pkg/msg/Alpha.idl",
          "#include \"pkg/msg/Zeta.idl\"\nmodule pkg { struct Alpha { string<pkg::LIMIT> s; }; };");
    write("pkg/msg/Zeta.idl", "module pkg { const long LIMIT = 4; struct Zeta { long z; }; };");
    write("pkg/notes.txt", "not IDL");
    sut_.add_idl_dir(dir_.string(), "--idl");
    sut_.add_idl_dir((dir_ / "pkg").string(), "--idl");  // the same files again: nothing declared twice
    EXPECT_NO_THROW(sut_.check_references());
    ASSERT_NE(sut_.find("pkg::Alpha"), nullptr);
    EXPECT_EQ(std::get<types::IdlStruct>(*sut_.find("pkg::Alpha")).members[0].type.bound, 4u);
    EXPECT_NE(sut_.find("pkg::Zeta"), nullptr);
}

TEST_F(TypeLibraryTest, ErrorsOfADirectoryNameTheFlagTheFileAndTheLine) {
    write("ok.idl", "struct Ok { long a; };");
    write("sub/broken.idl", "struct Broken {\n  long a;\n  long b\n};");
    EXPECT_EQ(config_error_of([&] { sut_.add_idl_dir(dir_.string(), "--idl"); }),
              "--idl: " + (dir_ / "sub/broken.idl").string() + ":4: expected ';' after the member, found '}'");
    EXPECT_EQ(config_error_of([&] { sut_.add_idl_dir("/nonexistent/tgw", "--idl"); }),
              "--idl: '/nonexistent/tgw' is not a directory");
}

TEST_F(TypeLibraryTest, GivesTheIdlTextOfATypeWithTheFilesItUsesFirst) {
    const std::string inner = "module m { struct Inner { long x; }; };\n";
    const std::string outer = "module m { struct Outer { sequence<Inner> items; }; };\n";
    const std::string unrelated = "struct Unrelated { long y; };\n";
    parse(outer, "outer.idl");
    parse(unrelated, "unrelated.idl");
    parse(inner, "inner.idl");
    EXPECT_EQ(sut_.idl_text("m::Outer"), inner + outer);
    EXPECT_EQ(sut_.idl_text("m::Inner"), inner);
    EXPECT_EQ(sut_.idl_text("no::Such"), "");
}

}  // namespace
}  // namespace tgw::test
