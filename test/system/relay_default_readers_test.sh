#!/usr/bin/env bash
# System test: programs on the base camp's own domain, behind tm-basecamp relay, with their vendors' defaults and
# nothing else: a Fast DDS participant with every default and a Cyclone DDS participant with no configuration at
# all (both discover by multicast on the camp's network) each receive everything a reliable Cyclone publisher on
# the robot writes, through the gateway and the testbed's shaped link. The relay is the camp's one participant
# on the WAN domain and names no peer: the gateway (--wan-peer-participants 1) announces itself to the camp's
# participant 0, which the relay's WAN participant must be. Needs root; skipped (77) otherwise.
#   relay_default_readers_test.sh BIN_DIR XV_PUB XV_SUB FASTDDS_DEFAULT_READER
set -euo pipefail
BIN="${1:?usage: relay_default_readers_test.sh BIN_DIR XV_PUB XV_SUB FASTDDS_DEFAULT_READER}"
PUB="${2:?}" SUB="${3:?}" FASTDDS_READER="${4:?}"
cd "$(dirname "$0")/../.."
# shellcheck source=test/system/system_test_lib.sh
source test/system/system_test_lib.sh
require_netns

RATE=1000000
COUNT=20
TIMEOUT_S=60
TOPIC="xv/blob/behind_the_relay"
LOCAL_DOMAIN=2
start_testbed "$RATE" relay-readers

"${tb[@]}" basecamp "$BIN/tm-basecamp" relay --domain 1 --interface "$basecamp_addr" \
    --local-domain "$LOCAL_DOMAIN" --duration $((TIMEOUT_S + 5)) >"$WORK/relay.out" 2>&1 &
relay_pid=$!
PIDS+=("$relay_pid")
"${tb[@]}" basecamp "$FASTDDS_READER" "$LOCAL_DOMAIN" "$TOPIC" tgw_xv::Blob "$COUNT" "$TIMEOUT_S" \
    >"$WORK/fastdds.out" 2>&1 &
fastdds_pid=$!
PIDS+=("$fastdds_pid")
"${tb[@]}" basecamp env -u CYCLONEDDS_URI "$SUB" "$LOCAL_DOMAIN" "$TOPIC" blob "$COUNT" 1 "$TIMEOUT_S" \
    >"$WORK/cyclone.out" 2>&1 &
cyclone_pid=$!
PIDS+=("$cyclone_pid")

"${tb[@]}" robot "$BIN/telemetry-gateway" --robot-domain 0 --wan-domain 1 --wan-peer "$basecamp_addr" \
    --wan-interface "$veth" --sensor "qdisc:$veth" --allow "xv/*" --wan-peer-participants 1 \
    --log "$WORK/robot-log.db" --duration $((TIMEOUT_S + 5)) >"$WORK/gateway.out" 2>&1 &
PIDS+=("$!")
"${tb[@]}" robot env CYCLONEDDS_URI="$robot_cyclone" "$PUB" 0 "$TOPIC" blob "$COUNT" 1 "$TIMEOUT_S" 100 \
    >"$WORK/pub.out" 2>&1 &
PIDS+=("$!")

fastdds_status=0 cyclone_status=0
wait "$fastdds_pid" || fastdds_status=$?
wait "$cyclone_pid" || cyclone_status=$?
kill -TERM "$relay_pid" 2>/dev/null || true
wait "$relay_pid" 2>/dev/null || true

for f in fastdds cyclone relay gateway pub; do
    echo "--- $f"
    tail -n 20 "$WORK/$f.out"
done
check "a Fast DDS participant with every default on the camp's domain received all $COUNT samples" "a == 0" \
    "$fastdds_status"
check "a Cyclone participant with no configuration on the camp's domain received all $COUNT samples" "a == 0" \
    "$cyclone_status"
exit "$fail"
