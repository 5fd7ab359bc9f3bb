// Passing a taken sample on to another writer as it came: tm-basecamp relay's lanes and the uplink's routes.
#pragma once

#include <fastdds/rtps/common/Time_t.h>
#include <fastrtps/types/TypesBase.h>

#include "passthrough/passthrough_type.hpp"

namespace eprosima::fastdds::dds {
class DataReader;
class DataWriter;
class SampleInfo;
}  // namespace eprosima::fastdds::dds

namespace tgw::passthrough {

/// Writes what a passthrough reader took (`data`, `info`) on `writer`, a passthrough writer of the same type,
/// stamped `stamp`: the sample in its instance, or that instance's dispose or unregister. The caller skips what an
/// unkeyed topic has no use for (a sample without valid data).
eprosima::fastrtps::types::ReturnCode_t pass_on(eprosima::fastdds::dds::DataWriter& writer, PassthroughData& data,
                                                const eprosima::fastdds::dds::SampleInfo& info, bool keyed,
                                                const eprosima::fastrtps::Time_t& stamp);

/// Deletes `reader` (its listener detached first), then `writer`; either may be null. The reader first: no callback
/// may find the writer gone.
void delete_reader_then_writer(eprosima::fastdds::dds::DataReader* reader, eprosima::fastdds::dds::DataWriter* writer);

}  // namespace tgw::passthrough
