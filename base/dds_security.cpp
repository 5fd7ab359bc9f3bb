#include "base/dds_security.hpp"

#include <algorithm>

namespace tgw::base {

void apply_dds_security(eprosima::fastdds::dds::DomainParticipantQos& qos, const SecurityFiles& files) {
    auto& properties = qos.properties().properties();
    const auto set = [&properties](const std::string& name, const std::string& value) {
        for (auto& property : properties) {
            if (property.name() == name) {
                property.value() = value;
                return;
            }
        }
        properties.emplace_back(name, value);
    };
    // Fast DDS reads "file://" and an absolute path (SecurityFiles holds absolute ones).
    const auto file = [](const std::string& path) { return "file://" + path; };
    set("dds.sec.auth.plugin", "builtin.PKI-DH");
    set("dds.sec.auth.builtin.PKI-DH.identity_ca", file(files.identity_ca));
    set("dds.sec.auth.builtin.PKI-DH.identity_certificate", file(files.certificate));
    set("dds.sec.auth.builtin.PKI-DH.private_key", file(files.private_key));
    set("dds.sec.access.plugin", "builtin.Access-Permissions");
    set("dds.sec.access.builtin.Access-Permissions.permissions_ca", file(files.permissions_ca));
    set("dds.sec.access.builtin.Access-Permissions.governance", file(files.governance));
    set("dds.sec.access.builtin.Access-Permissions.permissions", file(files.permissions));
    set("dds.sec.crypto.plugin", "builtin.AES-GCM-GMAC");
}

bool has_dds_security(const eprosima::fastdds::dds::DomainParticipantQos& qos) {
    const auto& properties = qos.properties().properties();
    return std::any_of(properties.begin(), properties.end(),
                       [](const auto& property) { return property.name() == "dds.sec.auth.plugin"; });
}

}  // namespace tgw::base
