#!/usr/bin/env bash
# System test: the camp's tools on loopback behind tm-basecamp relay with its defaults (issue 44's third part).
# The relay names its WAN interface and peer and nothing of the camp's domain: its camp participant then uses
# every interface but the WAN's. tm-basecamp record bound to loopback (as a ROS 2 tool with ROS_LOCALHOST_ONLY=1)
# records the paper's workload at 40,000 bit/s through the gateway: A, B and C >= 99 % on time, counted from the
# first sample; and no datagram of the camp's domain crosses the radio (the camp's veth). Needs root; skipped
# (77) otherwise.
#   camp_on_loopback_test.sh BIN_DIR
set -euo pipefail
BIN="${1:?usage: camp_on_loopback_test.sh BIN_DIR}"
BIN="$(cd "$BIN" && pwd)"
cd "$(dirname "$0")/../.."
# shellcheck source=test/system/system_test_lib.sh
source test/system/system_test_lib.sh
require_netns
require_tools sqlite3 python3

RATE=40000
PUBLISH_S=20
BOUND_S=$((PUBLISH_S + 30))  # upper bound only, should this script be killed hard
LOCAL_DOMAIN=7
# RTPS's ports of a domain: 7400 + 250 x domain, and the 249 after it (RTPS 9.6.1.1).
LOCAL_PORTS=($((7400 + 250 * LOCAL_DOMAIN)) $((7400 + 250 * LOCAL_DOMAIN + 249)))
start_testbed "$RATE" camp-loopback
camp_veth="$(TGW_TESTBED_ID="$TESTBED_ID" scripts/testbed info basecamp-veth)"

"${tb[@]}" basecamp python3 test/system/udp_port_count.py "$camp_veth" "${LOCAL_PORTS[@]}" >"$WORK/radio.out" 2>&1 &
counter_pid=$!
PIDS+=("$counter_pid")
for _ in $(seq 50); do grep -q listening "$WORK/radio.out" && break; sleep 0.1; done

"${tb[@]}" basecamp "$BIN/tm-basecamp" relay --domain 1 --peer "$robot_addr" --interface "$basecamp_addr" \
    --local-domain "$LOCAL_DOMAIN" --duration "$BOUND_S" >"$WORK/relay.out" 2>&1 &
relay_pid=$!
PIDS+=("$relay_pid")
"${tb[@]}" basecamp "$BIN/tm-basecamp" record --domain "$LOCAL_DOMAIN" --interface 127.0.0.1 --report-period 0 \
    --out "$WORK/camp.db" --duration "$BOUND_S" >"$WORK/record.out" 2>&1 &
record_pid=$!
PIDS+=("$record_pid")
start_paper_gateway "$BOUND_S"

sleep 2
start_paper_publisher "$PUBLISH_S"
finish_run "$sim_pid" "$gateway_pid" "$record_pid"
kill -TERM "$relay_pid" 2>/dev/null || true
wait "$relay_pid" 2>/dev/null || true
kill -TERM "$counter_pid" 2>/dev/null || true
wait "$counter_pid" 2>/dev/null || true
show_outputs "$WORK/record.out"
echo "--- relay"
tail -n 8 "$WORK/relay.out"

LOG="$WORK/robot-log.db" REC="$WORK/camp.db"
q() { camp_query "$1"; }
for row in "telemetry/A 1" "telemetry/B 2" "telemetry/C 5"; do
    read -r topic ttl_s <<<"$row"
    published="$(q "SELECT COUNT(*) FROM (SELECT source_time_ns FROM log.forwarded_samples WHERE topic = '$topic'
        UNION ALL SELECT source_time_ns FROM log.dropped_samples WHERE topic = '$topic')")"
    on_time="$(q "SELECT COUNT(*) FROM (SELECT source_ns, MIN(receive_ns) AS receive_ns FROM live_samples
        WHERE topic = '$topic' GROUP BY source_ns) WHERE receive_ns - source_ns <= $ttl_s * 1000000000")"
    echo "$topic: $on_time of $published on time at the camp's loopback"
    check "$topic on time at the camp's loopback: >= 99 % of what was published" "b >= 90 && a >= 0.99 * b" \
        "$on_time" "$published"
done
check "the relay said its camp participant is on loopback, kept off the WAN's $basecamp_addr" "a == 1" \
    "$(grep -c "camp's domain on 127.0.0.1 (kept off the WAN's $basecamp_addr)" "$WORK/relay.out" || true)"
crossed="$(tail -n 1 "$WORK/radio.out")"
echo "datagrams of the camp's domain across the radio: $crossed"
check "no datagram of the camp's domain (ports ${LOCAL_PORTS[0]} to ${LOCAL_PORTS[1]}) crossed the radio" \
    "a == 0" "${crossed:-missing}"
exit "$fail"
