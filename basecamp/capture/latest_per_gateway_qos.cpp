#include "basecamp/capture/latest_per_gateway_qos.hpp"

#include <fastdds/dds/publisher/Publisher.hpp>

namespace tgw::basecamp {

namespace fdds = eprosima::fastdds::dds;

fdds::DataWriterQos latest_per_gateway_qos(const fdds::Publisher& publisher) {
    fdds::DataWriterQos qos = publisher.get_default_datawriter_qos();
    qos.reliability().kind = fdds::RELIABLE_RELIABILITY_QOS;
    qos.durability().kind = fdds::VOLATILE_DURABILITY_QOS;
    qos.history().kind = fdds::KEEP_LAST_HISTORY_QOS;
    qos.history().depth = 1;
    qos.data_sharing().off();
    return qos;
}

}  // namespace tgw::basecamp
