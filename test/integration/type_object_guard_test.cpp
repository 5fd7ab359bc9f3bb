// A robot program built with `fastddsgen -typeobject` announces its type's TypeObject; where that holds a sequence
// of a type the discovering process does not know, Fast DDS 2.9 crashes in its discovery thread. The project's
// participants take the TypeObject before Fast DDS reads it (TypeObjectGuard). The publisher runs as another
// process, so that this one knows nothing of its types, as the gateway would not.
#include <gtest/gtest.h>

#include <mutex>
#include <thread>

#include <fastdds/dds/domain/DomainParticipant.hpp>
#include <fastdds/dds/domain/DomainParticipantFactory.hpp>

#include "base/peer_transport.hpp"
#include "passthrough/discovery.hpp"
#include "passthrough/type_object_idl.hpp"
#include "test/integration/child_process.hpp"
#include "test/integration/dds_test_support.hpp"

namespace tgw::test {
namespace {

using namespace std::chrono_literals;

TEST(TypeObjectGuardTest, ATypeObjectFastDdsWouldCrashOnReachesTheListenerAndNoFurther) {
    const int domain = TestDomains::for_this_process().robot;
    const std::string topic = "tgw_it/type_object_guard/convoy";

    std::mutex mutex;
    std::vector<passthrough::DiscoveredPublisher> discovered;
    passthrough::Discovery listener([&](passthrough::DiscoveredPublisher&& publisher) {
        std::lock_guard<std::mutex> lock(mutex);
        discovered.push_back(std::move(publisher));
    });
    auto* factory = fdds::DomainParticipantFactory::get_instance();
    fdds::DomainParticipantQos qos = factory->get_default_participant_qos();
    base::PeerTransport loopback;
    loopback.interface = "127.0.0.1";
    base::apply_peer_transport(qos, loopback, domain);
    fdds::DomainParticipant* participant =
        factory->create_participant(domain, qos, &listener, fdds::StatusMask::none());
    ASSERT_NE(participant, nullptr);

    ChildProcess publisher({TGW_ANNOUNCED_TYPES_PUBLISHER, std::to_string(domain), "Convoy", topic}, "/dev/null");
    ASSERT_TRUE(publisher.started());
    const auto convoy_found = [&] {
        std::lock_guard<std::mutex> lock(mutex);
        return std::any_of(discovered.begin(), discovered.end(),
                           [&](const passthrough::DiscoveredPublisher& p) { return p.topic == topic; });
    };
    const bool found = wait_until(convoy_found, 20s);
    // Long enough for Fast DDS to have built its DynamicType, had it been given the TypeObject.
    std::this_thread::sleep_for(1s);
    participant->set_listener(nullptr);
    factory->delete_participant(participant);
    ASSERT_TRUE(found) << "the publisher of " << topic << " was never discovered";

    std::lock_guard<std::mutex> lock(mutex);
    const auto it = std::find_if(discovered.begin(), discovered.end(),
                                 [&](const passthrough::DiscoveredPublisher& p) { return p.topic == topic; });
    EXPECT_EQ(it->type_name, "tgw_test::Convoy");
    ASSERT_NE(it->type_object, nullptr) << "the publisher announced a TypeObject";
    const passthrough::TypeObjectIdl idl = passthrough::type_object_idl(*it->type_object, it->type_name, {});
    EXPECT_NE(idl.missing.find("member 'members' of tgw_test::Convoy: refers to a type its publisher did not "
                               "announce"),
              std::string::npos)
        << idl.missing;
}

}  // namespace
}  // namespace tgw::test
