#include "passthrough/qos_file.hpp"

#include <tinyxml2.h>

#include <fastrtps/attributes/PublisherAttributes.h>
#include <fastrtps/xmlparser/XMLProfileManager.h>
#include <fastdds/dds/domain/DomainParticipantFactory.hpp>

#include "base/config_error.hpp"
#include "passthrough/dds_time.hpp"

namespace tgw::passthrough {

namespace fdds = eprosima::fastdds::dds;
using eprosima::fastrtps::types::ReturnCode_t;

void load_qos_file(const std::string& path) {
    // Fast DDS reports only that the file failed; read it first to name the line of a syntax error.
    tinyxml2::XMLDocument doc;
    const tinyxml2::XMLError err = doc.LoadFile(path.c_str());
    if (err == tinyxml2::XML_ERROR_FILE_NOT_FOUND || err == tinyxml2::XML_ERROR_FILE_COULD_NOT_BE_OPENED ||
        err == tinyxml2::XML_ERROR_FILE_READ_ERROR) {
        throw base::ConfigError("--qos " + path + ": cannot read the file");
    }
    if (err != tinyxml2::XML_SUCCESS) {
        throw base::ConfigError("--qos " + path + ":" + std::to_string(doc.ErrorLineNum()) + ": malformed XML (" +
                                doc.ErrorStr() + ")");
    }
    if (fdds::DomainParticipantFactory::get_instance()->load_XML_profiles_file(path) != ReturnCode_t::RETCODE_OK) {
        throw base::ConfigError("--qos " + path + ": Fast DDS rejected the profiles (its log above names the element)");
    }
}

std::optional<base::Duration> writer_profile_lifespan(const std::string& topic) {
    using eprosima::fastrtps::xmlparser::XMLP_ret;
    using eprosima::fastrtps::xmlparser::XMLProfileManager;
    eprosima::fastrtps::PublisherAttributes attributes;
    if (XMLProfileManager::fillPublisherAttributes(topic, attributes, false) != XMLP_ret::XML_OK) {
        return std::nullopt;
    }
    const std::optional<base::Duration> lifespan = to_duration(attributes.qos.m_lifespan.duration);
    if (!lifespan || *lifespan <= base::Duration::zero()) {
        return std::nullopt;
    }
    return lifespan;
}

namespace {

constexpr const char* UNDEFINED = "UNDEF";

}  // namespace

std::vector<DeclaredTopic> declared_topics(const std::string& path) {
    using eprosima::fastrtps::xmlparser::XMLP_ret;
    using eprosima::fastrtps::xmlparser::XMLProfileManager;
    tinyxml2::XMLDocument doc;
    if (doc.LoadFile(path.c_str()) != tinyxml2::XML_SUCCESS) {
        throw base::ConfigError("--qos " + path + ": cannot read the file");
    }
    std::vector<DeclaredTopic> topics;
    const tinyxml2::XMLElement* root = doc.RootElement();
    const tinyxml2::XMLElement* profiles = root ? root->FirstChildElement("profiles") : nullptr;
    for (const tinyxml2::XMLElement* writer = profiles ? profiles->FirstChildElement("data_writer") : nullptr;
         writer != nullptr; writer = writer->NextSiblingElement("data_writer")) {
        const char* name = writer->Attribute("profile_name");
        eprosima::fastrtps::PublisherAttributes attributes;
        // Fast DDS fills what the profile leaves out with "UNDEF".
        if (name == nullptr ||
            XMLProfileManager::fillPublisherAttributes(name, attributes, false) != XMLP_ret::XML_OK ||
            attributes.topic.topicDataType.to_string() == UNDEFINED) {
            continue;
        }
        const std::string topic_name = attributes.topic.topicName.to_string();
        if (topic_name != UNDEFINED && topic_name != name) {
            throw base::ConfigError("--qos " + path + ":" + std::to_string(writer->GetLineNum()) +
                                    ": data_writer profile '" + name + "' names topic '" + topic_name +
                                    "': a profile applies to the topic of its profile_name");
        }
        DeclaredTopic declared;
        declared.topic = name;
        declared.type_name = attributes.topic.topicDataType.to_string();
        declared.keyed = attributes.topic.topicKind == eprosima::fastrtps::rtps::WITH_KEY;
        declared.lifespan = to_duration(attributes.qos.m_lifespan.duration);
        declared.qos = attributes.qos;
        topics.push_back(std::move(declared));
    }
    return topics;
}

std::optional<fdds::DomainParticipantQos> participant_profile(const std::string& name) {
    fdds::DomainParticipantQos qos;
    if (fdds::DomainParticipantFactory::get_instance()->get_participant_qos_from_profile(name, qos) !=
        ReturnCode_t::RETCODE_OK) {
        return std::nullopt;
    }
    return qos;
}

}  // namespace tgw::passthrough
