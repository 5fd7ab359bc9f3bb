#!/usr/bin/env python3
"""Counts the UDP datagrams that cross a network interface, either way, from or to a port in [LOW, HIGH]; prints
the count when stopped (SIGTERM or SIGINT). A raw packet socket: needs root (or CAP_NET_RAW).
    udp_port_count.py IFACE LOW HIGH"""
import signal
import socket
import struct
import sys

ETH_P_ALL = 0x0003
ETH_P_IP = 0x0800
IPPROTO_UDP = 17


def main() -> int:
    if len(sys.argv) != 4:
        print(__doc__, file=sys.stderr)
        return 2
    iface, low, high = sys.argv[1], int(sys.argv[2]), int(sys.argv[3])
    sock = socket.socket(socket.AF_PACKET, socket.SOCK_RAW, socket.htons(ETH_P_ALL))
    sock.bind((iface, 0))
    sock.settimeout(0.2)
    count = 0
    stopped = False

    def stop(_signum, _frame):
        nonlocal stopped
        stopped = True

    signal.signal(signal.SIGTERM, stop)
    signal.signal(signal.SIGINT, stop)
    print("listening", flush=True)
    while not stopped:
        try:
            frame = sock.recv(65535)
        except socket.timeout:
            continue
        except InterruptedError:
            continue
        if len(frame) < 14 + 20 + 8 or struct.unpack_from("!H", frame, 12)[0] != ETH_P_IP:
            continue
        header_bytes = (frame[14] & 0x0F) * 4
        if frame[14 + 9] != IPPROTO_UDP or len(frame) < 14 + header_bytes + 8:
            continue
        source, destination = struct.unpack_from("!HH", frame, 14 + header_bytes)
        if low <= source <= high or low <= destination <= high:
            count += 1
    print(count, flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
