#include "basecamp/capture/camp_participant.hpp"

#include <iostream>

#include <fastdds/dds/domain/DomainParticipant.hpp>
#include <fastdds/dds/domain/DomainParticipantFactory.hpp>

#include "base/config_error.hpp"
#include "base/dds_security.hpp"
#include "base/receive_buffer.hpp"

namespace tgw::basecamp {

namespace fdds = eprosima::fastdds::dds;

fdds::DomainParticipant* create_camp_participant(int domain, const base::PeerTransport& transport,
                                                 const std::optional<base::SecurityFiles>& security,
                                                 const std::string& name, passthrough::Discovery& discovery) {
    auto* factory = fdds::DomainParticipantFactory::get_instance();
    fdds::DomainParticipantQos qos = factory->get_default_participant_qos();
    qos.name(name);
    base::apply_peer_transport(qos, transport, domain);
    base::warn_if_receive_buffer_capped(std::cerr, "tm-basecamp", "--receive-buffer", transport.receive_buffer_bytes);
    if (security)
        base::apply_dds_security(qos, *security);
    fdds::DomainParticipant* participant =
        factory->create_participant(domain, qos, &discovery, fdds::StatusMask::none());
    if (participant == nullptr)
        throw base::ConfigError("--domain: cannot create a DDS participant on domain " + std::to_string(domain) +
                                (security ? " (see Fast DDS's log about --security)" : ""));
    discovery.ignore_participant(participant->guid().guidPrefix);
    return participant;
}

}  // namespace tgw::basecamp
