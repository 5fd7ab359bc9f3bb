// SecurityFiles::load: an identity made by scripts/make-certs passes; a missing file, a certificate of another CA, a
// key of another certificate, tampered or foreign governance and permissions are refused, the file named.
#include <gtest/gtest.h>

#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

#include "base/dds_security.hpp"
#include "base/security_files.hpp"
#include "test/fakes/config_error_of.hpp"

namespace tgw::base {
namespace {

namespace fs = std::filesystem;
using test::config_error_of;

class SecurityFilesTest : public ::testing::Test {
  protected:
    /// The identities of the ctest fixture (test/security/make_test_identities.sh), made here when the binary runs
    /// alone.
    static void SetUpTestSuite() {
        if (!fs::exists(fs::path(TGW_TEST_CERTS) / "gateway" / "permissions.p7s")) {
            const std::string command = std::string(TGW_MAKE_CERTS) + " " + TGW_TEST_CERTS + " >/dev/null";
            ASSERT_EQ(std::system(command.c_str()), 0) << command;
        }
    }

    void SetUp() override {
        dir_ = fs::temp_directory_path() / ("tgw_security_files_" + std::to_string(::getpid()) + "_" +
                                            ::testing::UnitTest::GetInstance()->current_test_info()->name());
        fs::remove_all(dir_);
        fs::create_directories(dir_);
    }

    void TearDown() override { fs::remove_all(dir_); }

    static fs::path identity(const std::string& name) { return fs::path(TGW_TEST_CERTS) / name; }

    /// A copy of the identity `name` in the test's directory.
    std::string copy_of(const std::string& name) {
        const fs::path to = dir_ / name;
        fs::create_directories(to);
        for (const auto& entry : fs::directory_iterator(identity(name)))
            fs::copy_file(entry.path(), to / entry.path().filename(), fs::copy_options::overwrite_existing);
        return to.string();
    }

    /// Replaces the first `from` in `file` by `to`.
    static void replace_in(const std::string& file, const std::string& from, const std::string& to) {
        std::ifstream in(file, std::ios::binary);
        std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
        const auto at = text.find(from);
        ASSERT_NE(at, std::string::npos) << from << " not in " << file;
        text.replace(at, from.size(), to);
        std::ofstream(file, std::ios::binary | std::ios::trunc) << text;
    }

    static std::string load_error(const std::string& dir) {
        return config_error_of([&] { SecurityFiles::load(dir, "--wan-security"); });
    }

    fs::path dir_;
};

TEST_F(SecurityFilesTest, AcceptsEachIdentityMakeCertsMade) {
    for (const char* name : {"gateway", "basecamp", "limited", "intruder"}) {
        EXPECT_EQ(load_error(identity(name).string()), "<no error>") << name;
    }
}

// The relay sizes the commands it sends by whether its WAN participant is secured.
TEST_F(SecurityFilesTest, AParticipantIsSecuredOnceTheIdentityIsApplied) {
    eprosima::fastdds::dds::DomainParticipantQos qos;
    EXPECT_FALSE(has_dds_security(qos));
    apply_dds_security(qos, SecurityFiles::load(identity("basecamp").string(), "--security"));
    EXPECT_TRUE(has_dds_security(qos));
}

TEST_F(SecurityFilesTest, GivesEachFileAsAnAbsolutePath) {
    const std::string dir = copy_of("gateway");
    ASSERT_EQ(::chdir(dir_.c_str()), 0);
    const SecurityFiles sut = SecurityFiles::load("gateway", "--wan-security");
    EXPECT_EQ(sut.certificate, dir + "/cert.pem");
    EXPECT_EQ(sut.private_key, dir + "/key.pem");
    EXPECT_EQ(sut.identity_ca, dir + "/identity_ca.pem");
    EXPECT_EQ(sut.permissions_ca, dir + "/permissions_ca.pem");
    EXPECT_EQ(sut.governance, dir + "/governance.p7s");
    EXPECT_EQ(sut.permissions, dir + "/permissions.p7s");
}

TEST_F(SecurityFilesTest, NamesTheDirectoryThatIsNotThere) {
    EXPECT_EQ(load_error("/nonexistent/tgw-identity"),
              "--wan-security /nonexistent/tgw-identity: not a directory (an identity made by scripts/make-certs)");
}

TEST_F(SecurityFilesTest, NamesEachMissingFile) {
    for (const char* file :
         {"identity_ca.pem", "cert.pem", "key.pem", "permissions_ca.pem", "governance.p7s", "permissions.p7s"}) {
        const std::string dir = copy_of("gateway");
        fs::remove(fs::path(dir) / file);
        EXPECT_EQ(load_error(dir).rfind("--wan-security " + dir + "/" + file + ": missing", 0), 0u) << load_error(dir);
    }
}

TEST_F(SecurityFilesTest, RefusesACertificateOfAnotherCa) {
    const std::string dir = copy_of("gateway");
    fs::copy_file(identity("intruder") / "cert.pem", fs::path(dir) / "cert.pem", fs::copy_options::overwrite_existing);
    fs::copy_file(identity("intruder") / "key.pem", fs::path(dir) / "key.pem", fs::copy_options::overwrite_existing);
    const std::string error = load_error(dir);
    EXPECT_EQ(error.rfind("--wan-security " + dir + "/cert.pem: not accepted by " + dir + "/identity_ca.pem", 0), 0u)
        << error;
    EXPECT_NE(error.find("another CA"), std::string::npos) << error;
}

TEST_F(SecurityFilesTest, RefusesTheKeyOfAnotherCertificate) {
    const std::string dir = copy_of("gateway");
    fs::copy_file(identity("basecamp") / "key.pem", fs::path(dir) / "key.pem", fs::copy_options::overwrite_existing);
    EXPECT_EQ(load_error(dir), "--wan-security " + dir + "/key.pem: not the key of " + dir + "/cert.pem");
}

TEST_F(SecurityFilesTest, RefusesTamperedPermissions) {
    const std::string dir = copy_of("gateway");
    replace_in(dir + "/permissions.p7s", "<default>DENY</default>", "<default>ALLOW</default>");
    const std::string error = load_error(dir);
    EXPECT_EQ(error.rfind("--wan-security " + dir + "/permissions.p7s: its signature does not verify with " + dir +
                              "/permissions_ca.pem: tampered with, or signed by another CA",
                          0),
              0u)
        << error;
}

TEST_F(SecurityFilesTest, RefusesTamperedGovernance) {
    const std::string dir = copy_of("gateway");
    replace_in(dir + "/governance.p7s", "<rtps_protection_kind>SIGN", "<rtps_protection_kind>NONE");
    const std::string error = load_error(dir);
    EXPECT_EQ(error.rfind("--wan-security " + dir + "/governance.p7s: its signature does not verify", 0), 0u) << error;
}

TEST_F(SecurityFilesTest, RefusesPermissionsSignedByAnotherCa) {
    const std::string dir = copy_of("gateway");
    fs::copy_file(identity("intruder") / "permissions.p7s", fs::path(dir) / "permissions.p7s",
                  fs::copy_options::overwrite_existing);
    const std::string error = load_error(dir);
    EXPECT_EQ(error.rfind("--wan-security " + dir + "/permissions.p7s: its signature does not verify", 0), 0u) << error;
}

TEST_F(SecurityFilesTest, RefusesPermissionsThatGrantNothingToTheCertificatesSubject) {
    const std::string dir = copy_of("gateway");
    fs::copy_file(identity("basecamp") / "permissions.p7s", fs::path(dir) / "permissions.p7s",
                  fs::copy_options::overwrite_existing);
    EXPECT_EQ(load_error(dir), "--wan-security " + dir + "/permissions.p7s: grants nothing to " + dir +
                                   "/cert.pem's subject 'CN=gateway,O=telemetry-gateway test,C=FR'");
}

TEST_F(SecurityFilesTest, RefusesACaFileThatIsNotACertificate) {
    const std::string dir = copy_of("gateway");
    std::ofstream(dir + "/identity_ca.pem", std::ios::trunc) << "not a certificate\n";
    EXPECT_EQ(load_error(dir).rfind("--wan-security " + dir + "/identity_ca.pem: not a PEM certificate", 0), 0u)
        << load_error(dir);
}

TEST_F(SecurityFilesTest, RefusesADocumentThatIsNotSMime) {
    const std::string dir = copy_of("gateway");
    fs::copy_file(fs::path(dir) / "permissions.xml", fs::path(dir) / "permissions.p7s",
                  fs::copy_options::overwrite_existing);
    EXPECT_EQ(load_error(dir).rfind("--wan-security " + dir + "/permissions.p7s: not an S/MIME (PKCS#7) document", 0),
              0u)
        << load_error(dir);
}

}  // namespace
}  // namespace tgw::base
