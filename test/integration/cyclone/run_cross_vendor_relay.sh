#!/usr/bin/env bash
# Cross-vendor relay test: Cyclone DDS publishers on the robot domain -> telemetry-gateway -> the WAN domain ->
# tm-basecamp relay -> Cyclone DDS subscribers (reliable, as ROS 2 readers are) on the camp's own domain, on
# loopback. Passes when both subscribers (an unkeyed topic with samples up to 5 kB, a keyed topic with 50
# instances) receive every sample with its bytes, source timestamp and instance intact. GATEWAY_FLAGS go to the
# gateway: --wan-mode compact runs the same through bundles (the 5 kB samples in chunks), which the relay unpacks.
#
#   run_cross_vendor_relay.sh GATEWAY TM_BASECAMP XV_PUB XV_SUB [GATEWAY_FLAGS...]
set -euo pipefail
[ $# -ge 4 ] || { echo "usage: $0 GATEWAY TM_BASECAMP XV_PUB XV_SUB [GATEWAY_FLAGS...]" >&2; exit 2; }
GATEWAY="$1" BASECAMP="$2" PUB="$3" SUB="$4"
shift 4
GATEWAY_FLAGS=("$@")
# shellcheck source=test/integration/cyclone/xv_lib.sh
source "$(dirname "$0")/xv_lib.sh"

LOCAL_DOMAIN=$((WAN_DOMAIN + 1))
BLOB_TOPIC="xv/relay/blob/$RUN"
KEYED_TOPIC="xv/relay/keyed/$RUN"
COUNT=24
KEYED_COUNT=100
INSTANCES=50
TIMEOUT_S=60

echo "cross-vendor relay: robot domain $ROBOT_DOMAIN, WAN domain $WAN_DOMAIN, local domain $LOCAL_DOMAIN"
start sub-blob "$SUB" "$LOCAL_DOMAIN" "$BLOB_TOPIC" blob "$COUNT" 1 "$TIMEOUT_S"
SUB_BLOB=$LAST_PID
start sub-keyed "$SUB" "$LOCAL_DOMAIN" "$KEYED_TOPIC" keyed "$KEYED_COUNT" "$INSTANCES" "$TIMEOUT_S"
SUB_KEYED=$LAST_PID
# The relay first: it is participant 0 of the WAN domain on this host, where the gateway announces itself.
start relay "$BASECAMP" relay --domain "$WAN_DOMAIN" --peer 127.0.0.1 --interface 127.0.0.1 \
    --local-domain "$LOCAL_DOMAIN" --local-interface 127.0.0.1 --duration $((TIMEOUT_S + 10))
sleep 1
start_gateway $((TIMEOUT_S + 10)) "${GATEWAY_FLAGS[@]}"
start pub-blob "$PUB" "$ROBOT_DOMAIN" "$BLOB_TOPIC" blob "$COUNT" 1 "$TIMEOUT_S"
start pub-keyed "$PUB" "$ROBOT_DOMAIN" "$KEYED_TOPIC" keyed "$KEYED_COUNT" "$INSTANCES" "$TIMEOUT_S" 0

status=0
wait "$SUB_BLOB" || status=1
wait "$SUB_KEYED" || status=1
finish "$status" sub-blob sub-keyed relay pub-blob pub-keyed gateway
