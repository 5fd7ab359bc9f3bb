#include "passthrough/passthrough_route.hpp"

#include <fastdds/dds/publisher/Publisher.hpp>
#include <fastdds/dds/subscriber/Subscriber.hpp>
#include <fastdds/dds/topic/Topic.hpp>

#include "passthrough/pass_on.hpp"
#include "passthrough/take_each.hpp"

namespace tgw::passthrough {

namespace fdds = eprosima::fastdds::dds;
using eprosima::fastrtps::types::ReturnCode_t;

PassthroughRoute::~PassthroughRoute() {
    delete_reader_then_writer(reader_, writer_);
}

bool PassthroughRoute::open_writer(fdds::Publisher& publisher, fdds::Topic* topic, const fdds::DataWriterQos& qos) {
    if (topic != nullptr) {
        writer_ = publisher.create_datawriter(topic, qos, &writer_matches_, fdds::StatusMask::publication_matched());
    }
    return writer_ != nullptr;
}

bool PassthroughRoute::attach_reader(fdds::Subscriber& subscriber, fdds::Topic* topic, const fdds::DataReaderQos& qos) {
    if (writer_ != nullptr && topic != nullptr) {
        reader_ = subscriber.create_datareader(topic, qos, this, fdds::StatusMask::all());
    }
    return reader_ != nullptr;
}

void PassthroughRoute::detach_reader() {
    delete_reader_then_writer(reader_, nullptr);
    reader_ = nullptr;
}

void PassthroughRoute::on_data_available(fdds::DataReader* reader) {
    take_each<PassthroughData>(*reader, [this](PassthroughData& data, const fdds::SampleInfo& info) {
        if (!info.valid_data && !keyed_) {
            return;  // an unkeyed topic's one instance: nothing to pass on
        }
        const std::optional<eprosima::fastrtps::Time_t> stamp = admit(data, info);
        if (!stamp) {
            return;
        }
        const bool reader_matched = writer_matches_.matched.load() > 0;
        written(pass_on(*writer_, data, info, keyed_, *stamp), reader_matched);
    });
}

}  // namespace tgw::passthrough
