#!/usr/bin/env bash
# System test (issue 45, backfill with a real robot's mix): an independent Cyclone DDS publisher with its defaults
# (mix_pub: six topics, Lifespan = TTL, a keyed one with six instances, 6,000-byte images that fragment on the
# wire) through the gateway with its defaults over the testbed at 20,000 bit/s; the radio down for OUTAGE_S
# seconds mid-run, so that every topic, the images (TTL 20 s) included, has samples expire into the on-robot log;
# then the link idles at 100,000 bit/s for IDLE_S seconds. The camp's `tm-basecamp relay --out` records. Cyclone
# sends no key hash by default: the gateway computes the joints' from their IDL (--idl test/system/mix), as its
# message asks a user to.
# Checks: per topic, every sample the gateway received (forwarded or logged) is in the camp's recording once, live
# or backfilled; backfilled joints keep their instance (the log's key); backfilled images keep their bytes (equal
# to the log's row). Needs root and the Cyclone programs; skipped (77) otherwise. About 80 s; ctest's backfill_mix.
#   backfill_mix_test.sh BIN_DIR
set -euo pipefail
BIN="${1:?usage: backfill_mix_test.sh BIN_DIR}"
BIN="$(cd "$BIN" && pwd)"
cd "$(dirname "$0")/../.."
# shellcheck source=test/system/system_test_lib.sh
source test/system/system_test_lib.sh
require_netns
require_tools sqlite3
[ -x "$BIN/mix_pub" ] || { echo "backfill_mix: $BIN/mix_pub is missing (it needs Cyclone DDS: scripts/build)" >&2; exit 77; }

LIVE_RATE=20000
IDLE_RATE=100000
PUBLISH_S=40
OUTAGE_AT_S=8
OUTAGE_S=25
IDLE_S=${IDLE_S:-40}
BOUND_S=$((PUBLISH_S + IDLE_S + 40))  # upper bound only, should this script be killed hard
start_testbed "$LIVE_RATE" backfill-mix
[ -z "${TGW_TEST_KEEP:-}" ] || trap 'mkdir -p "$TGW_TEST_KEEP" && cp -r "$WORK"/. "$TGW_TEST_KEEP"/; stop_testbed' EXIT

start_recording_relay "$BOUND_S"
"${tb[@]}" robot "$BIN/telemetry-gateway" --robot-domain 0 --wan-domain 1 --wan-peer "$basecamp_addr" \
    --wan-interface "$veth" --sensor "qdisc:$veth" --log "$WORK/robot-log.db" --idl test/system/mix \
    --duration "$BOUND_S" \
    >"$WORK/gateway.out" 2>&1 &
gateway_pid=$!
PIDS+=("$gateway_pid")
sleep 3
"${tb[@]}" robot env CYCLONEDDS_URI="$robot_cyclone" "$BIN/mix_pub" 0 "$PUBLISH_S" >"$WORK/robot.out" 2>&1 &
sim_pid=$!
PIDS+=("$sim_pid")
sleep "$OUTAGE_AT_S"
"${tb[@]}" robot ip link set "$veth" down
sleep "$OUTAGE_S"
"${tb[@]}" robot ip link set "$veth" up
wait_link_up robot "$veth" >/dev/null
wait "$sim_pid" || true
TGW_TESTBED_ID="$TESTBED_ID" scripts/testbed set-rate "$IDLE_RATE" >/dev/null
echo "mix_pub for ${PUBLISH_S} s at $LIVE_RATE bit/s, the radio down for ${OUTAGE_S} s from ${OUTAGE_AT_S} s;" \
    "then $IDLE_RATE bit/s for ${IDLE_S} s"
sleep "$IDLE_S"
finish_run "$sim_pid" "$gateway_pid" "$record_pid"
show_outputs "$WORK/record.out"

LOG="$WORK/robot-log.db" REC="$WORK/basecamp.db"
q() { camp_query "$1"; }

echo
echo "== the archive"
for topic in mix/hazard mix/pose mix/joints mix/battery mix/image mix/science; do
    # A sample is its source time and instance: the six joints of one tick share their time.
    read -r received logged <<<"$(q "SELECT (SELECT COUNT(*) FROM log.forwarded_samples WHERE topic = '$topic') +
        (SELECT COUNT(*) FROM log.dropped_samples WHERE topic = '$topic'),
        (SELECT COUNT(*) FROM log.dropped_samples WHERE topic = '$topic')" | tr '|' ' ')"
    read -r archived backfilled twice <<<"$(q "SELECT COUNT(*), SUM(backfilled), SUM(n > 1) FROM (SELECT
        MAX(backfilled) AS backfilled, COUNT(*) AS n FROM samples WHERE topic = '$topic'
        GROUP BY source_ns, hex(instance))" | tr '|' ' ')"
    said="$topic: the recording holds every one of the $received the gateway received"
    check "$said ($archived; $logged logged, ${backfilled:-0} backfilled, ${twice:-0} twice)" \
        "a == b && b > 0 && c == 0" "${archived:-0}" "${received:-0}" "${twice:-0}"
done

echo
echo "== what backfill kept"
read -r joints same_key <<<"$(q "SELECT COUNT(*), SUM(s.instance IS NOT NULL AND s.instance = d.instance_key)
    FROM samples s JOIN log.dropped_samples d ON d.id = s.row_id WHERE s.backfilled AND s.topic = 'mix/joints'" |
    tr '|' ' ')"
check "backfilled joints keep their instance ($same_key of $joints)" "b > 0 && a == b" "${same_key:-0}" \
    "${joints:-0}"
read -r frames same_bytes bytes <<<"$(q "SELECT COUNT(*), SUM(s.payload = d.payload), MIN(length(s.payload))
    FROM samples s JOIN log.dropped_samples d ON d.id = s.row_id WHERE s.backfilled AND s.topic = 'mix/image'" |
    tr '|' ' ')"
check "backfilled images keep their bytes ($same_bytes of $frames equal to the log's, the least ${bytes:-0} B)" \
    "b > 0 && a == b" "${same_bytes:-0}" "${frames:-0}"
grep '^backfill on tgw/backfill' "$WORK/gateway.out" || true
exit "$fail"
