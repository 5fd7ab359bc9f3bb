// DDS Security on one participant: Fast DDS's builtin plugins, configured from an identity's files.
#pragma once

#include <fastdds/dds/domain/qos/DomainParticipantQos.hpp>

#include "base/security_files.hpp"

namespace tgw::base {

/// Sets on `qos` the properties of Fast DDS's builtin.PKI-DH authentication, builtin.AES-GCM-GMAC cryptography and
/// builtin.Access-Permissions access control with `files`' identity, CAs, governance and permissions. What the
/// governance says (here: everything encrypted, no unauthenticated participant) then applies to the participant.
void apply_dds_security(eprosima::fastdds::dds::DomainParticipantQos& qos, const SecurityFiles& files);

/// Whether `qos` authenticates its participant (apply_dds_security() did, or a profile's properties): its messages
/// then carry the security submessages (core::WireModel::with_security()).
bool has_dds_security(const eprosima::fastdds::dds::DomainParticipantQos& qos);

}  // namespace tgw::base
