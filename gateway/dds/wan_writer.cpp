#include "gateway/dds/wan_writer.hpp"

#include <iostream>
#include <utility>

#include <fastdds/dds/publisher/DataWriter.hpp>
#include <fastdds/dds/publisher/Publisher.hpp>

#include "gateway/dds/datagram_coalescer.hpp"
#include "gateway/dds/repair_desk.hpp"
#include "passthrough/dds_time.hpp"
#include "passthrough/passthrough_type.hpp"

namespace tgw::dds {

namespace fdds = eprosima::fastdds::dds;
using eprosima::fastrtps::types::ReturnCode_t;

WanWriter::WanWriter(fdds::DataWriter* writer, std::unique_ptr<passthrough::WriterMatchCounter> matches,
                     std::string topic, bool keyed, Deleter deleter)
    : writer_(writer),
      matches_(std::move(matches)),
      deleter_(std::move(deleter)),
      topic_(std::move(topic)),
      keyed_(keyed),
      reliable_(writer->get_qos().reliability().kind == fdds::RELIABLE_RELIABILITY_QOS),
      latched_(writer->get_qos().durability().kind != fdds::VOLATILE_DURABILITY_QOS),
      lifespan_(passthrough::to_duration(writer->get_qos().lifespan().duration)) {}

WanWriter::~WanWriter() {
    fdds::DataWriter* writer = nullptr;
    {
        std::lock_guard<std::mutex> lock(mutex_);
        writer = writer_;
    }
    // Outside the lock: the router's deleter takes its own, which it holds while it detaches and replaces.
    if (writer != nullptr)
        deleter_(writer);
}

void WanWriter::detach() {
    std::lock_guard<std::mutex> lock(mutex_);
    writer_ = nullptr;
    matches_->matched.store(0);
}

void WanWriter::replace(fdds::DataWriter* writer) {
    std::lock_guard<std::mutex> lock(mutex_);
    writer_ = writer;
    failure_reported_.store(false);
    // The successor starts with no history: the camp's late joiners must still get each instance's last change.
    // It has no reader yet, so these writes only fill its history.
    for (core::Sample& change : latched_history_.live(base::WallClock::now(), lifespan_)) {
        write_nts(change);
    }
}

WriteResult WanWriter::write(core::Sample& sample, AfterWrite after) {
    std::lock_guard<std::mutex> lock(mutex_);
    const ReturnCode_t rc = write_nts(sample);
    if (rc != ReturnCode_t::RETCODE_OK) {
        if (!failure_reported_.exchange(true)) {
            std::cerr << "telemetry-gateway: WAN write failed on " << topic_ << " (code " << rc() << ")\n";
        }
        return WriteResult::failed;
    }
    if (latched_) {
        if (after == AfterWrite::payload_spent && !RepairDesk::PacedWatch::holding_here()) {
            latched_history_.keep_taking_payload(sample);
        } else {
            latched_history_.keep(sample);
        }
    }
    return WriteResult::ok;
}

ReturnCode_t WanWriter::write_nts(core::Sample& sample) {
    if (writer_ == nullptr) {
        return ReturnCode_t::RETCODE_NOT_ENABLED;
    }
    passthrough::PassthroughData data;
    const std::size_t payload_bytes = sample.payload.size();
    // Borrowed for the write, which copies it once into the change, and handed back after.
    data.payload = std::move(sample.payload);
    fdds::InstanceHandle_t handle = fdds::HANDLE_NIL;
    if (keyed_) {
        if (sample.key.valid) {
            for (std::size_t i = 0; i < sample.key.bytes.size(); ++i) {
                data.key.value[i] = sample.key.bytes[i];
            }
        }
        handle = data.key.isDefined() ? data.key : passthrough::PassthroughType::UNKNOWN_INSTANCE;
    }
    const auto stamp = passthrough::to_dds_time(sample.source_time);
    const ReturnCode_t rc = [&] {
        const DatagramCoalescer::DeferScope may_wait;
        // Only a reliable writer repairs: a best-effort lane's samples need not be remembered.
        RepairDesk::WriteScope repairs_belong_to(sample.topic, sample.deadline, reliable_, latched_, payload_bytes);
        switch (sample.kind) {
            case core::SampleKind::dispose:
                return writer_->dispose_w_timestamp(&data, handle, stamp);
            case core::SampleKind::unregister:
                return writer_->unregister_instance_w_timestamp(&data, handle, stamp);
            case core::SampleKind::data:
                break;
        }
        return writer_->write_w_timestamp(&data, handle, stamp);
    }();
    sample.payload = std::move(data.payload);
    return rc;
}

}  // namespace tgw::dds
