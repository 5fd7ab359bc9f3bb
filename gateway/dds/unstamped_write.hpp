// Marks a WAN write whose sample carries its own write time, so that the transport may leave out its INFO_TS.
#pragma once

namespace tgw::dds {

/// While one lives on a thread, the messages that thread's write sends may go without the INFO_TS that stamps
/// the sample (CoalescingTransportDescriptor::strip_timestamp): compact mode's bundles, whose encoding holds the
/// time they were written (compact::Bundle::write_ns). 12 bytes of every bundle. A reader then sees no source
/// timestamp on the DDS sample. Nests.
class UnstampedWrite {
  public:
    UnstampedWrite() { ++depth(); }
    ~UnstampedWrite() { --depth(); }
    UnstampedWrite(const UnstampedWrite&) = delete;
    UnstampedWrite& operator=(const UnstampedWrite&) = delete;

    static bool active() { return depth() > 0; }

  private:
    static int& depth() {
        thread_local int value = 0;
        return value;
    }
};

}  // namespace tgw::dds
