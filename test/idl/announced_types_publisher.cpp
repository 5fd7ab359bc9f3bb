// A robot program as a Fast DDS user writes one with `fastddsgen -typeobject`: it registers its types' TypeObjects,
// so that its writer announces one in discovery, and publishes until killed. Tests run it as another process, whose
// TypeObjectFactory knows types the test's participants do not.
//
//   announced_types_publisher DOMAIN TYPE TOPIC    TYPE: FlatReading or Convoy
//
// UDP on loopback only (tgw::base::apply_peer_transport with an interface), found as the gateway finds robot
// programs.
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <thread>

#include <fastdds/dds/domain/DomainParticipant.hpp>
#include <fastdds/dds/domain/DomainParticipantFactory.hpp>
#include <fastdds/dds/publisher/DataWriter.hpp>
#include <fastdds/dds/publisher/Publisher.hpp>

#include "AnnouncedTypesPubSubTypes.h"
#include "AnnouncedTypesTypeObject.h"
#include "base/peer_transport.hpp"

namespace fdds = eprosima::fastdds::dds;

int main(int argc, char** argv) {
    if (argc != 4) {
        std::fprintf(stderr, "usage: %s DOMAIN FlatReading|Convoy TOPIC\n", argv[0]);
        return 2;
    }
    const int domain = std::atoi(argv[1]);
    const std::string type = argv[2];
    registerAnnouncedTypesTypes();

    auto* factory = fdds::DomainParticipantFactory::get_instance();
    fdds::DomainParticipantQos qos = factory->get_default_participant_qos();
    tgw::base::PeerTransport loopback;
    loopback.interface = "127.0.0.1";
    tgw::base::apply_peer_transport(qos, loopback, domain);
    fdds::DomainParticipant* participant = factory->create_participant(domain, qos);
    fdds::TypeSupport support(type == "Convoy" ? static_cast<fdds::TopicDataType*>(new tgw_test::ConvoyPubSubType())
                                               : new tgw_test::FlatReadingPubSubType());
    if (participant == nullptr || support.register_type(participant) != ReturnCode_t::RETCODE_OK)
        return 1;
    fdds::Topic* topic = participant->create_topic(argv[3], support.get_type_name(), fdds::TOPIC_QOS_DEFAULT);
    fdds::Publisher* publisher = participant->create_publisher(fdds::PUBLISHER_QOS_DEFAULT);
    fdds::DataWriter* writer = publisher->create_datawriter(topic, fdds::DATAWRITER_QOS_DEFAULT);
    if (writer == nullptr)
        return 1;
    for (std::uint32_t i = 0;; ++i) {
        if (type == "Convoy") {
            tgw_test::Convoy convoy;
            convoy.members().resize(1);
            convoy.members()[0].sensor_id(i % 4);
            writer->write(&convoy);
        } else {
            // Four sensors: a writer keeps 10 instances by default (Fast DDS's max_instances).
            tgw_test::FlatReading reading;
            reading.sensor_id(i % 4);
            reading.ok(true);
            reading.f64(20.5 + i % 4);
            reading.label("left wheel");
            reading.unit("rad/s");
            reading.history({20.5, 20.25});
            writer->write(&reading);
        }
        std::this_thread::sleep_for(std::chrono::milliseconds(200));
    }
}
