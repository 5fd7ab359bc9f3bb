#!/usr/bin/env bash
# System test: programs on the base camp's own domain, behind tm-basecamp relay with its defaults (no
# --local-interface), and nothing else configured: a Fast DDS participant with every default, a Cyclone DDS
# participant with no configuration at all, a Cyclone participant bound to loopback and tm-basecamp echo bound to
# loopback (as ROS 2 with ROS_LOCALHOST_ONLY=1) each receive everything a reliable Cyclone publisher on the robot
# writes, through the gateway and the testbed's shaped link. The relay keeps its camp participant off the radio
# (camp_on_loopback_test.sh counts what crosses it); a tool with no configuration here, where the radio's veth is
# the only interface but loopback, still hears it on this host. The relay names no peer: the gateway
# (--wan-peer-participants 1) announces itself to the camp's participant 0, which the relay's WAN participant
# must be. Needs root; skipped (77) otherwise.
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
loopback_cyclone="<CycloneDDS><Domain Id=\"any\"><General><Interfaces><NetworkInterface address=\"127.0.0.1\"/></Interfaces></General></Domain></CycloneDDS>"

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
"${tb[@]}" basecamp env CYCLONEDDS_URI="$loopback_cyclone" "$SUB" "$LOCAL_DOMAIN" "$TOPIC" blob "$COUNT" 1 \
    "$TIMEOUT_S" >"$WORK/cyclone-lo.out" 2>&1 &
cyclone_lo_pid=$!
PIDS+=("$cyclone_lo_pid")
"${tb[@]}" basecamp "$BIN/tm-basecamp" echo --domain "$LOCAL_DOMAIN" --interface 127.0.0.1 "$TOPIC" \
    --count "$COUNT" --timeout "$TIMEOUT_S" >"$WORK/echo-lo.out" 2>&1 &
echo_lo_pid=$!
PIDS+=("$echo_lo_pid")

"${tb[@]}" robot "$BIN/telemetry-gateway" --robot-domain 0 --wan-domain 1 --wan-peer "$basecamp_addr" \
    --wan-interface "$veth" --sensor "qdisc:$veth" --allow "xv/*" --wan-peer-participants 1 \
    --log "$WORK/robot-log.db" --duration $((TIMEOUT_S + 5)) >"$WORK/gateway.out" 2>&1 &
PIDS+=("$!")
"${tb[@]}" robot env CYCLONEDDS_URI="$robot_cyclone" "$PUB" 0 "$TOPIC" blob "$COUNT" 1 "$TIMEOUT_S" 100 \
    >"$WORK/pub.out" 2>&1 &
PIDS+=("$!")

fastdds_status=0 cyclone_status=0 cyclone_lo_status=0 echo_lo_status=0
wait "$fastdds_pid" || fastdds_status=$?
wait "$cyclone_pid" || cyclone_status=$?
wait "$cyclone_lo_pid" || cyclone_lo_status=$?
wait "$echo_lo_pid" || echo_lo_status=$?
kill -TERM "$relay_pid" 2>/dev/null || true
wait "$relay_pid" 2>/dev/null || true

for f in fastdds cyclone cyclone-lo echo-lo relay gateway pub; do
    echo "--- $f"
    tail -n 20 "$WORK/$f.out"
done
check "a Fast DDS participant with every default on the camp's domain received all $COUNT samples" "a == 0" \
    "$fastdds_status"
check "a Cyclone participant with no configuration on the camp's domain received all $COUNT samples" "a == 0" \
    "$cyclone_status"
check "a Cyclone participant bound to loopback received all $COUNT samples" "a == 0" "$cyclone_lo_status"
check "tm-basecamp echo bound to loopback received all $COUNT samples" "a == 0" "$echo_lo_status"
check "the relay said where the camp's domain is, and not on the WAN's $basecamp_addr" "a == 1" \
    "$(grep -c "camp's domain on 127.0.0.1 (kept off the WAN's $basecamp_addr)" "$WORK/relay.out" || true)"
exit "$fail"
