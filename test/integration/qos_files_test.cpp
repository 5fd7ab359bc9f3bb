// Every XML file in qos/ loads into Fast DDS, and the paper workload's profiles say what docs/design.md §2 says.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>

#include <fastrtps/xmlparser/XMLProfileManager.h>
#include <fastdds/dds/domain/DomainParticipantFactory.hpp>
#include <fastdds/dds/publisher/Publisher.hpp>

#include "base/config_error.hpp"
#include "passthrough/qos_file.hpp"
#include "test/integration/dds_test_support.hpp"
#include "test/integration/error_log_counter.hpp"

namespace tgw::test {
namespace {

class QosFilesTest : public ::testing::Test {
  protected:
    void SetUp() override { ErrorLogCounter::instance().take_errors(); }
    void TearDown() override {
        const auto errors = ErrorLogCounter::instance().take_errors();
        EXPECT_TRUE(errors.empty()) << errors.size() << " Fast DDS errors, first: " << errors.front();
    }
};

std::vector<std::filesystem::path> qos_files() {
    std::vector<std::filesystem::path> files;
    for (const auto& entry : std::filesystem::directory_iterator(TGW_QOS_DIR)) {
        if (entry.path().extension() == ".xml") {
            files.push_back(entry.path());
        }
    }
    return files;
}

TEST_F(QosFilesTest, EveryXmlFileInQosLoads) {
    const auto files = qos_files();
    ASSERT_FALSE(files.empty());
    for (const auto& file : files) {
        // The gateway loads one --qos file; files that define the same profiles (the paper's best-effort and
        // reliable variants) cannot share a process.
        eprosima::fastrtps::xmlparser::XMLProfileManager::DeleteInstance();
        EXPECT_NO_THROW(passthrough::load_qos_file(file.string())) << file;
    }
}

TEST_F(QosFilesTest, PaperWorkloadProfilesCarryTheTtlsAsLifespan) {
    passthrough::load_qos_file(std::string(TGW_QOS_DIR) + "/paper_workload.xml");
    TestParticipant p(TestDomains::for_this_process().robot, fdds::PARTICIPANT_QOS_DEFAULT);
    ASSERT_TRUE(p.ok());
    fdds::Publisher* publisher = p.participant()->create_publisher(fdds::PUBLISHER_QOS_DEFAULT);
    const std::pair<const char*, int> expected[] = {
        {"telemetry/A", 1}, {"telemetry/B", 2}, {"telemetry/C", 5}, {"telemetry/D", 20}};
    for (const auto& [topic, seconds] : expected) {
        fdds::DataWriterQos qos;
        ASSERT_EQ(publisher->get_datawriter_qos_from_profile(topic, qos), ReturnCode_t::RETCODE_OK) << topic;
        EXPECT_EQ(qos.lifespan().duration, eprosima::fastrtps::Duration_t(seconds, 0)) << topic;
        EXPECT_EQ(qos.reliability().kind, fdds::BEST_EFFORT_RELIABILITY_QOS) << topic;
    }
}

TEST_F(QosFilesTest, WriterProfileLifespanNeedsNoParticipant) {
    passthrough::load_qos_file(std::string(TGW_QOS_DIR) + "/paper_workload.xml");
    EXPECT_EQ(passthrough::writer_profile_lifespan("telemetry/A"), std::chrono::seconds(1));
    EXPECT_EQ(passthrough::writer_profile_lifespan("telemetry/D"), std::chrono::seconds(20));
    EXPECT_FALSE(passthrough::writer_profile_lifespan("no/such/topic"));
}

TEST_F(QosFilesTest, PaperWorkloadDeclaresItsFourTopicsWithTheirType) {
    const std::string path = std::string(TGW_QOS_DIR) + "/paper_workload.xml";
    passthrough::load_qos_file(path);
    const auto declared = passthrough::declared_topics(path);
    ASSERT_EQ(declared.size(), 4u);
    const char* names[] = {"telemetry/A", "telemetry/B", "telemetry/C", "telemetry/D"};
    for (std::size_t i = 0; i < 4; ++i) {
        EXPECT_EQ(declared[i].topic, names[i]);
        EXPECT_EQ(declared[i].type_name, "tgw::idl::PaperMessage");
        EXPECT_FALSE(declared[i].keyed);
        EXPECT_EQ(declared[i].qos.m_reliability.kind, fdds::BEST_EFFORT_RELIABILITY_QOS);
    }
    EXPECT_EQ(declared[0].lifespan, std::chrono::seconds(1));
}

TEST_F(QosFilesTest, AProfileForAnotherTopicThanItsNameIsAConfigErrorNamingTheLine) {
    const std::string path = "/tmp/tgw_qos_other_topic_" + std::to_string(::getpid()) + ".xml";
    {
        std::ofstream out(path);
        out << "<?xml version=\"1.0\"?>\n<dds xmlns=\"http://www.eprosima.com/XMLSchemas/fastRTPS_Profiles\">\n"
               "<profiles>\n<data_writer profile_name=\"tgw_test/a\">\n"
               "<topic><name>tgw_test/b</name><dataType>T</dataType></topic>\n</data_writer>\n</profiles>\n</dds>\n";
    }
    passthrough::load_qos_file(path);
    try {
        passthrough::declared_topics(path);
        ADD_FAILURE() << "no ConfigError";
    } catch (const base::ConfigError& e) {
        const std::string what = e.what();
        EXPECT_NE(what.find(path + ":4:"), std::string::npos) << what;
        EXPECT_NE(what.find("tgw_test/b"), std::string::npos) << what;
    }
    std::remove(path.c_str());
}

TEST_F(QosFilesTest, ParticipantProfilesExist) {
    passthrough::load_qos_file(std::string(TGW_QOS_DIR) + "/gateway_participants.xml");
    const auto wan = passthrough::participant_profile(passthrough::WAN_PARTICIPANT_PROFILE);
    ASSERT_TRUE(wan);
    EXPECT_EQ(wan->wire_protocol().builtin.discovery_config.leaseDuration_announcementperiod,
              eprosima::fastrtps::Duration_t(20, 0));
    EXPECT_TRUE(passthrough::participant_profile(passthrough::ROBOT_PARTICIPANT_PROFILE));
}

TEST_F(QosFilesTest, MalformedXmlNamesTheFileAndLine) {
    const std::string path = "/tmp/tgw_qos_bad_" + std::to_string(::getpid()) + ".xml";
    {
        std::ofstream out(path);
        out << "<?xml version=\"1.0\"?>\n<dds>\n<profiles>\n<data_writer profile_name=\"x\">\n</dds>\n";
    }
    try {
        passthrough::load_qos_file(path);
        ADD_FAILURE() << "no ConfigError";
    } catch (const base::ConfigError& e) {
        const std::string what = e.what();
        EXPECT_NE(what.find(path), std::string::npos) << what;
        EXPECT_NE(what.find(":4:"), std::string::npos) << what;  // the unclosed element
    }
    std::remove(path.c_str());
}

TEST_F(QosFilesTest, MissingFileIsAConfigError) {
    EXPECT_THROW(passthrough::load_qos_file("/nonexistent/tgw.xml"), base::ConfigError);
}

}  // namespace
}  // namespace tgw::test
