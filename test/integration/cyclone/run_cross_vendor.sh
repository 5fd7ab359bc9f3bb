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

WORK="$(mktemp -d "${TMPDIR:-/tmp}/tgw-xv.XXXXXX")"
PIDS=()
cleanup() {
    local pid
    for pid in "${PIDS[@]}"; do kill -TERM "$pid" 2>/dev/null || true; done
    for pid in "${PIDS[@]}"; do wait "$pid" 2>/dev/null || true; done
}
trap cleanup EXIT

# Domain ids of this run: port 7400 + 250 * id must stay below 65536, so ids up to 232.
ROBOT_DOMAIN=$((120 + (RANDOM + $$) % 50))
WAN_DOMAIN=$((ROBOT_DOMAIN + 55))
RUN="$$_$RANDOM"
BLOB_TOPIC="xv/blob/$RUN"
KEYED_TOPIC="xv/keyed/$RUN"
COUNT=24
# The keyed topic: 50 instances, 2 samples each, written in bursts.
KEYED_COUNT=100
INSTANCES=50
TIMEOUT_S=60

# Cyclone on loopback only: no multicast (lo has none), discovery by unicast to the well-known participant
# ports on 127.0.0.1, where the gateway's robot and WAN participants listen.
export CYCLONEDDS_URI="<CycloneDDS><Domain Id=\"any\"><General><Interfaces><NetworkInterface address=\"127.0.0.1\"/></Interfaces><AllowMulticast>false</AllowMulticast></General><Discovery><ParticipantIndex>auto</ParticipantIndex><MaxAutoParticipantIndex>20</MaxAutoParticipantIndex><Peers><Peer Address=\"127.0.0.1\"/></Peers></Discovery></Domain></CycloneDDS>"

echo "cross-vendor: robot domain $ROBOT_DOMAIN, WAN domain $WAN_DOMAIN, topics $BLOB_TOPIC, $KEYED_TOPIC"
"$SUB" "$WAN_DOMAIN" "$BLOB_TOPIC" blob "$COUNT" 1 "$TIMEOUT_S" >"$WORK/sub-blob.out" 2>&1 &
SUB_BLOB=$!
"$SUB" "$WAN_DOMAIN" "$KEYED_TOPIC" keyed "$KEYED_COUNT" "$INSTANCES" "$TIMEOUT_S" >"$WORK/sub-keyed.out" 2>&1 &
SUB_KEYED=$!
PIDS+=("$SUB_BLOB" "$SUB_KEYED")

"$GATEWAY" --robot-domain "$ROBOT_DOMAIN" --wan-domain "$WAN_DOMAIN" --wan-peer 127.0.0.1 \
    --wan-interface 127.0.0.1 --sensor fixed:50000000 --allow "xv/*" --log "$WORK/robot-log.db" \
    --duration $((TIMEOUT_S + 10)) >"$WORK/gateway.out" 2>&1 &
PIDS+=("$!")

"$PUB" "$ROBOT_DOMAIN" "$BLOB_TOPIC" blob "$COUNT" 1 "$TIMEOUT_S" >"$WORK/pub-blob.out" 2>&1 &
PIDS+=("$!")
"$PUB" "$ROBOT_DOMAIN" "$KEYED_TOPIC" keyed "$KEYED_COUNT" "$INSTANCES" "$TIMEOUT_S" 0 >"$WORK/pub-keyed.out" 2>&1 &
PIDS+=("$!")

status=0
wait "$SUB_BLOB" || status=1
wait "$SUB_KEYED" || status=1
cleanup
PIDS=()
for f in sub-blob sub-keyed pub-blob pub-keyed gateway; do
    echo "--- $f"
    cat "$WORK/$f.out"
done
# "WAN datagrams: M samples' messages in D datagrams ..."
read -r messages datagrams < <(sed -n "s/^WAN datagrams: \([0-9]*\) samples' messages in \([0-9]*\) datagrams.*/\1 \2/p" \
    "$WORK/gateway.out") || true
if [ -z "${messages:-}" ] || [ "$datagrams" -ge "$messages" ]; then
    echo "cross-vendor: the gateway packed no WAN datagram (messages ${messages:-?}, datagrams ${datagrams:-?})"
    status=1
fi
if [ "$status" -eq 0 ]; then
    rm -rf "$WORK"
    echo "cross-vendor: PASSED"
else
    echo "cross-vendor: FAILED (files in $WORK)"
fi
exit "$status"
