// An operator's --qos file decides each topic's TTL: any text loads into profiles or gives a ConfigError naming
// the file (and the line where there is one), and every topic it declares resolves to a TTL that is a finite,
// positive duration, the profile's Lifespan exactly when that applies (docs/design.md §4). Each input is written
// to a file of its own (Fast DDS loads a path once) and the profiles are cleared after it.
#include <unistd.h>

#include <chrono>
#include <fstream>
#include <iterator>
#include <sstream>
#include <string>

#include <fastrtps/xmlparser/XMLProfileManager.h>
#include <fastdds/dds/log/Log.hpp>

#include "base/config_error.hpp"
#include "passthrough/qos_file.hpp"
#include "passthrough/ttl_resolver.hpp"
#include "test/fuzz/fuzz_target.hpp"

namespace tgw::fuzz {

namespace {

std::string file_text(const std::string& path) {
    std::ifstream in(path);
    return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

std::string writer_profile(const std::string& name, const std::string& lifespan, const std::string& topic) {
    return "<data_writer profile_name=\"" + name + "\">" + topic + "<qos><lifespan><duration>" + lifespan +
           "</duration></lifespan></qos></data_writer>";
}

std::string profiles(const std::string& body) {
    return "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n"
           "<dds xmlns=\"http://www.eprosima.com/XMLSchemas/fastRTPS_Profiles\"><profiles>\n" +
           body + "\n</profiles></dds>\n";
}

}  // namespace

std::vector<std::string> seeds() {
    const std::string typed = "<topic><name>telemetry/A</name><dataType>tgw::idl::PaperMessage</dataType></topic>";
    return {
        file_text(TGW_QOS_DIR "/paper_workload.xml"),
        file_text(TGW_QOS_DIR "/paper_workload_reliable.xml"),
        file_text(TGW_QOS_DIR "/gateway_participants.xml"),
        profiles(writer_profile("telemetry/A", "<sec>1</sec><nanosec>0</nanosec>", typed)),
        profiles(writer_profile("a", "<sec>0</sec><nanosec>0</nanosec>", "") +
                 writer_profile("b", "<sec>-3</sec>", "") + writer_profile("c", "<sec>DURATION_INFINITY</sec>", "") +
                 writer_profile("d", "<sec>2147483647</sec><nanosec>999999999</nanosec>", "")),
        profiles(writer_profile("telemetry/A", "<sec>1</sec>",
                                "<topic><name>telemetry/B</name><dataType>T</dataType></topic>")),
    };
}

}  // namespace tgw::fuzz

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    using namespace tgw;
    static const bool quiet = [] {
        eprosima::fastdds::dds::Log::ClearConsumers();  // Fast DDS logs every element it rejects
        return true;
    }();
    (void)quiet;
    static unsigned long inputs = 0;
    const std::string path =
        "/tmp/tgw_qos_file_fuzz_" + std::to_string(::getpid()) + "_" + std::to_string(inputs++) + ".xml";
    {
        std::ofstream out(path, std::ios::binary);
        out.write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
    }
    const auto names_the_file = [&path](const base::ConfigError& e) {
        return std::string(e.what()).rfind("--qos " + path, 0) == 0;
    };
    try {
        passthrough::load_qos_file(path);
        std::vector<passthrough::DeclaredTopic> declared;
        try {
            declared = passthrough::declared_topics(path);
        } catch (const base::ConfigError& e) {
            TGW_FUZZ_CHECK(names_the_file(e));
        }
        constexpr base::Duration DEFAULT_TTL = std::chrono::seconds(5);
        for (const passthrough::DeclaredTopic& topic : declared) {
            TGW_FUZZ_CHECK(!topic.topic.empty() && !topic.type_name.empty());
            const std::optional<base::Duration> profile = passthrough::writer_profile_lifespan(topic.topic);
            TGW_FUZZ_CHECK(!profile || *profile > base::Duration::zero());
            const passthrough::ResolvedTtl ttl = passthrough::resolve_ttl(profile, topic.lifespan, DEFAULT_TTL);
            TGW_FUZZ_CHECK(ttl.ttl > base::Duration::zero() && ttl.ttl < base::Duration::max());
            TGW_FUZZ_CHECK((ttl.source == passthrough::TtlSource::profile) ==
                           (profile && *profile != base::Duration::max()));
            TGW_FUZZ_CHECK(ttl.source != passthrough::TtlSource::fallback || ttl.ttl == DEFAULT_TTL);
        }
        passthrough::participant_profile(passthrough::ROBOT_PARTICIPANT_PROFILE);
        passthrough::participant_profile(passthrough::WAN_PARTICIPANT_PROFILE);
    } catch (const base::ConfigError& e) {
        TGW_FUZZ_CHECK(names_the_file(e));
    }
    eprosima::fastrtps::xmlparser::XMLProfileManager::DeleteInstance();
    std::remove(path.c_str());
    return 0;
}
