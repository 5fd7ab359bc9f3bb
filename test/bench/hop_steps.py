#!/usr/bin/env python3
"""Where the gateway's per-sample CPU time goes, step by step, from `perf script -F tid,ip,sym` call stacks.

Reads the stacks of a perf recording of gateway_hop_bench (scripts/hop-profile makes one) and keeps those on the
gateway's path: every stack that holds the robot lane's listener, in which Fast DDS's receive thread takes a
sample and, with the budget free, writes it to the WAN. Each such stack counts for the innermost step of the path
it is in, and as allocation or locking when its innermost frame is the allocator's or a mutex's. Prints each
step's share of the path's samples and the CPU time per forwarded sample it stands for.

    hop_steps.py STACKS --rate HZ --samples N
"""
import argparse
import collections
import re
import sys

# The path's steps, innermost first. A stack counts for the step its leaf-most matching frame names; where one
# frame matches two steps, the earlier one.
STEPS = [
    ("send: Fast DDS's setsockopt(SO_SNDTIMEO) per datagram", r"setsockopt"),
    ("send: sendto, the kernel's loopback delivery", r"sendto"),
    ("send: Fast DDS's UDP transport", r"UDPTransportInterface|UDPv4Transport|UDPChannelResource|asio::"),
    ("send: the WAN coalescer", r"CoalescingTransport|DatagramCoalescer|RepairDesk|RtpsDatagram|early_heartbeats"),
    ("write: the payload copied into the change", r"PassthroughType::serialize"),
    ("write: Fast DDS's change, history and message",
     r"DataWriterImpl|RTPSWriter|StatelessWriter|StatefulWriter|RTPSMessageGroup|WriterHistory|LocatorSelector"),
    ("write: the latched copy (transient local)", r"LatchedHistory"),
    ("write: WanWriter (its lock, stamp and key)", r"WanWriter::"),
    ("sink: the bridge and lane writer looked up", r"TopicTable::find|TopicBridge::write"),
    ("sink: the on-robot log's row", r"RobotLog|log_forwarded"),
    ("sink: GatewaySink::forward, the processing histogram", r"GatewaySink|LatencyHistogram"),
    ("scheduler: push and release", r"Scheduler::|DeadlineQueue|LinkBudget|ProtectedTopics"),
    ("forwarding loop: lock, outbox", r"ForwardingLoop|WriteOutbox"),
    ("take: the payload copied out of the cache", r"PassthroughType::deserialize"),
    ("take: Fast DDS's take", r"DataReaderImpl|DataReader::take|ReaderHistory|DataReaderHistory"),
    ("take: the lane listener", r"LaneListener"),
]
ALLOCATION = re.compile(r"malloc|_int_free|cfree|operator new|operator delete|__libc_free|tcache")
LOCKING = re.compile(r"pthread_mutex|lll_|futex|pthread_cond|std::mutex")
PATH = "LaneListener::on_data_available"


def stacks(lines):
    stack = []
    for line in lines:
        line = line.rstrip("\n")
        if not line.strip():
            if stack:
                yield stack
            stack = []
        elif line[0] in "\t ":
            parts = line.strip().split(" ", 1)
            stack.append(parts[1] if len(parts) > 1 else "")
    if stack:
        yield stack


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("stacks", help="perf script -F tid,ip,sym output; - for stdin")
    parser.add_argument("--rate", type=float, required=True, help="perf record's sampling rate, Hz")
    parser.add_argument("--samples", type=int, required=True, help="samples the gateway forwarded meanwhile")
    args = parser.parse_args()
    steps = [(name, re.compile(pattern)) for name, pattern in STEPS]
    by_step = collections.Counter()
    allocation = collections.Counter()
    locking = collections.Counter()
    total = 0
    with (sys.stdin if args.stacks == "-" else open(args.stacks)) as lines:
        for stack in stacks(lines):
            if not any(PATH in frame for frame in stack):
                continue
            total += 1
            step = next((name for frame in stack for name, pattern in steps if pattern.search(frame)), "other")
            by_step[step] += 1
            if ALLOCATION.search(stack[0]):
                allocation[step] += 1
            elif LOCKING.search(stack[0]):
                locking[step] += 1
    if total == 0:
        print("hop_steps: no stack on the gateway's path (was gateway_hop_bench recorded with --call-graph dwarf?)",
              file=sys.stderr)
        return 1
    us_per_stack = 1e6 / args.rate / args.samples
    print(f"the gateway's path: {total} stacks at {args.rate:g} Hz over {args.samples} samples forwarded, "
          f"{total * us_per_stack:.1f} us of CPU per sample")
    print(f"{'share':>6} {'us':>6} {'alloc':>6} {'locks':>6}  step")
    for name, _ in STEPS + [("other", None)]:
        count = by_step[name]
        if count == 0:
            continue
        print(f"{100.0 * count / total:5.1f}% {count * us_per_stack:6.2f} {allocation[name] * us_per_stack:6.2f} "
              f"{locking[name] * us_per_stack:6.2f}  {name}")
    print(f"{'':6} {total * us_per_stack:6.2f} {sum(allocation.values()) * us_per_stack:6.2f} "
          f"{sum(locking.values()) * us_per_stack:6.2f}  the whole path")
    return 0


if __name__ == "__main__":
    sys.exit(main())
