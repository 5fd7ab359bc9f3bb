#include "passthrough/pass_on.hpp"

#include <fastdds/dds/publisher/DataWriter.hpp>
#include <fastdds/dds/publisher/Publisher.hpp>
#include <fastdds/dds/subscriber/DataReader.hpp>
#include <fastdds/dds/subscriber/SampleInfo.hpp>
#include <fastdds/dds/subscriber/Subscriber.hpp>

namespace tgw::passthrough {

namespace fdds = eprosima::fastdds::dds;
using eprosima::fastrtps::types::ReturnCode_t;

ReturnCode_t pass_on(fdds::DataWriter& writer, PassthroughData& data, const fdds::SampleInfo& info, bool keyed,
                     const eprosima::fastrtps::Time_t& stamp) {
    fdds::InstanceHandle_t handle = fdds::HANDLE_NIL;
    if (keyed) {
        data.key = info.instance_handle;
        handle = info.instance_handle.isDefined() ? info.instance_handle : PassthroughType::UNKNOWN_INSTANCE;
    }
    if (info.valid_data) {
        return writer.write_w_timestamp(&data, handle, stamp);
    }
    if (info.instance_state == fdds::NOT_ALIVE_DISPOSED_INSTANCE_STATE) {
        return writer.dispose_w_timestamp(&data, handle, stamp);
    }
    return writer.unregister_instance_w_timestamp(&data, handle, stamp);
}

void delete_reader_then_writer(fdds::DataReader* reader, fdds::DataWriter* writer) {
    if (reader != nullptr) {
        reader->set_listener(nullptr);
        const_cast<fdds::Subscriber*>(reader->get_subscriber())->delete_datareader(reader);
    }
    if (writer != nullptr) {
        const_cast<fdds::Publisher*>(writer->get_publisher())->delete_datawriter(writer);
    }
}

}  // namespace tgw::passthrough
