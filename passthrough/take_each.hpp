// The one take loop: every sample a reader holds, in order, each into the same object. A payload the caller leaves
// in it keeps its capacity for the next sample; one moved out (the robot lanes, the recorder, echo) does not, so
// each of their samples allocates anew.
#pragma once

#include <fastrtps/types/TypesBase.h>
#include <fastdds/dds/subscriber/DataReader.hpp>
#include <fastdds/dds/subscriber/SampleInfo.hpp>

namespace tgw::passthrough {

/// Takes every sample `reader` holds and hands each to `each(sample, info)`, disposes and unregisters included.
template <typename Sample, typename Each>
void take_each(eprosima::fastdds::dds::DataReader& reader, Each&& each) {
    Sample sample;
    eprosima::fastdds::dds::SampleInfo info;
    while (reader.take_next_sample(&sample, &info) == eprosima::fastrtps::types::ReturnCode_t::RETCODE_OK) {
        each(sample, info);
    }
}

/// Takes every sample `reader` holds and hands those with data to `each(sample, info)`; a dispose or unregister
/// carries none.
template <typename Sample, typename Each>
void take_valid(eprosima::fastdds::dds::DataReader& reader, Each&& each) {
    take_each<Sample>(reader, [&each](Sample& sample, const eprosima::fastdds::dds::SampleInfo& info) {
        if (info.valid_data) {
            each(sample, info);
        }
    });
}

}  // namespace tgw::passthrough
