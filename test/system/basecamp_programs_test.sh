#!/usr/bin/env bash
# System test: three base-camp programs at once, each as its users set it up, all receive everything through the
# gateway over the testbed's shaped link: a Fast DDS participant with every default (multicast discovery, no
# peers), a Cyclone DDS participant with the standard unicast set-up (participant index auto, the robot as
# peer) and a reliable reader, and tm-basecamp record. The robot side is a reliable Cyclone publisher. Needs
# root; skipped (77) otherwise.
#   basecamp_programs_test.sh BIN_DIR XV_PUB XV_SUB FASTDDS_DEFAULT_READER
set -euo pipefail
BIN="${1:?usage: basecamp_programs_test.sh BIN_DIR XV_PUB XV_SUB FASTDDS_DEFAULT_READER}"
PUB="${2:?}" SUB="${3:?}" FASTDDS_READER="${4:?}"
cd "$(dirname "$0")/../.."
# shellcheck source=test/system/system_test_lib.sh
source test/system/system_test_lib.sh
require_netns

RATE=1000000
COUNT=20
TIMEOUT_S=60
TOPIC="xv/blob/programs"
start_testbed "$RATE" programs

# Cyclone at the base camp as its documentation sets up unicast discovery towards a known host.
basecamp_cyclone="<CycloneDDS><Domain Id=\"any\"><General><Interfaces><NetworkInterface address=\"$basecamp_addr\"/></Interfaces><AllowMulticast>false</AllowMulticast></General><Discovery><ParticipantIndex>auto</ParticipantIndex><Peers><Peer Address=\"$robot_addr\"/></Peers></Discovery></Domain></CycloneDDS>"

# The base camp first: tm-basecamp record, then the two vendors' programs (participants 0, 1 and 2 there).
"${tb[@]}" basecamp "$BIN/tm-basecamp" record --domain 1 --peer "$robot_addr" --interface "$basecamp_addr" \
    --out "$WORK/basecamp.db" --duration $((TIMEOUT_S + 5)) >"$WORK/record.out" 2>&1 &
PIDS+=("$!")
record_pid=$!
sleep 1
"${tb[@]}" basecamp "$FASTDDS_READER" 1 "$TOPIC" tgw_xv::Blob "$COUNT" "$TIMEOUT_S" >"$WORK/fastdds.out" 2>&1 &
fastdds_pid=$!
PIDS+=("$fastdds_pid")
sleep 1
"${tb[@]}" basecamp env CYCLONEDDS_URI="$basecamp_cyclone" "$SUB" 1 "$TOPIC" blob "$COUNT" 1 "$TIMEOUT_S" \
    >"$WORK/cyclone.out" 2>&1 &
cyclone_pid=$!
PIDS+=("$cyclone_pid")

"${tb[@]}" robot "$BIN/telemetry-gateway" --robot-domain 0 --wan-domain 1 --wan-peer "$basecamp_addr" \
    --wan-interface "$veth" --sensor "qdisc:$veth" --allow "xv/*" --log "$WORK/robot-log.db" \
    --duration $((TIMEOUT_S + 5)) >"$WORK/gateway.out" 2>&1 &
PIDS+=("$!")
"${tb[@]}" robot env CYCLONEDDS_URI="$robot_cyclone" "$PUB" 0 "$TOPIC" blob "$COUNT" 1 "$TIMEOUT_S" 100 \
    >"$WORK/pub.out" 2>&1 &
PIDS+=("$!")

# The sequence number is the payload's first field, after the 4-byte encapsulation header.
recorded() {
    sqlite3 "$WORK/basecamp.db" \
        "select count(distinct substr(hex(payload), 9, 8)) from samples where topic = '$TOPIC'" 2>/dev/null || echo 0
}
fastdds_status=0 cyclone_status=0
wait "$fastdds_pid" || fastdds_status=$?
wait "$cyclone_pid" || cyclone_status=$?
# The recorder subscribes once it has discovered the gateway's writer, and commits every so often: the
# publisher repeats its samples, so wait for them all (at most TIMEOUT_S) before stopping it.
for _ in $(seq 1 $((TIMEOUT_S * 2))); do
    [ "$(recorded)" -ge "$COUNT" ] && break
    sleep 0.5
done
kill -TERM "$record_pid" 2>/dev/null || true
wait "$record_pid" 2>/dev/null || true
recorded="$(recorded)"

for f in fastdds cyclone record gateway pub; do
    echo "--- $f"
    tail -n 20 "$WORK/$f.out"
done
check "a Fast DDS participant with every default received all $COUNT samples" "a == 0" "$fastdds_status"
check "a Cyclone participant (unicast, index auto, a reliable reader) received all $COUNT samples" "a == 0" \
    "$cyclone_status"
check "tm-basecamp record recorded all $COUNT samples" "a >= b" "${recorded:-0}" "$COUNT"
exit "$fail"
