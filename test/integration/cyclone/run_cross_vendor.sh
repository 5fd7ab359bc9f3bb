#!/usr/bin/env bash
# Cross-vendor test: Cyclone DDS publishers on the robot domain -> telemetry-gateway -> Cyclone DDS
# subscribers on the WAN domain, on loopback only, with domain ids of this run only. Passes when both
# subscribers (an unkeyed topic with samples up to 5 kB, a keyed topic with 50 instances) receive every
# sample with its bytes, source timestamp and instance intact. The keyed topic's small samples come in bursts,
# which the gateway packs into shared WAN datagrams: its summary must show fewer datagrams than messages.
#
#   run_cross_vendor.sh GATEWAY XV_PUB XV_SUB
set -euo pipefail
[ $# -eq 3 ] || { echo "usage: $0 GATEWAY XV_PUB XV_SUB" >&2; exit 2; }
GATEWAY="$1" PUB="$2" SUB="$3"
# shellcheck source=test/integration/cyclone/xv_lib.sh
source "$(dirname "$0")/xv_lib.sh"

BLOB_TOPIC="xv/blob/$RUN"
KEYED_TOPIC="xv/keyed/$RUN"
COUNT=24
# The keyed topic: 50 instances, 2 samples each, written in bursts.
KEYED_COUNT=100
INSTANCES=50
TIMEOUT_S=60

echo "cross-vendor: robot domain $ROBOT_DOMAIN, WAN domain $WAN_DOMAIN, topics $BLOB_TOPIC, $KEYED_TOPIC"
start sub-blob "$SUB" "$WAN_DOMAIN" "$BLOB_TOPIC" blob "$COUNT" 1 "$TIMEOUT_S"
SUB_BLOB=$LAST_PID
start sub-keyed "$SUB" "$WAN_DOMAIN" "$KEYED_TOPIC" keyed "$KEYED_COUNT" "$INSTANCES" "$TIMEOUT_S"
SUB_KEYED=$LAST_PID
start_gateway $((TIMEOUT_S + 10))
start pub-blob "$PUB" "$ROBOT_DOMAIN" "$BLOB_TOPIC" blob "$COUNT" 1 "$TIMEOUT_S"
start pub-keyed "$PUB" "$ROBOT_DOMAIN" "$KEYED_TOPIC" keyed "$KEYED_COUNT" "$INSTANCES" "$TIMEOUT_S" 0

status=0
wait "$SUB_BLOB" || status=1
wait "$SUB_KEYED" || status=1
stop_all
# "WAN datagrams: M samples' messages in D datagrams ..."
read -r messages datagrams < <(sed -n "s/^WAN datagrams: \([0-9]*\) samples' messages in \([0-9]*\) datagrams.*/\1 \2/p" \
    "$WORK/gateway.out") || true
if [ -z "${messages:-}" ] || [ "$datagrams" -ge "$messages" ]; then
    echo "cross-vendor: the gateway packed no WAN datagram (messages ${messages:-?}, datagrams ${datagrams:-?})"
    status=1
fi
finish "$status" sub-blob sub-keyed pub-blob pub-keyed gateway
