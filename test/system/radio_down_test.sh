#!/usr/bin/env bash
# System test (issue 44, "The radio's life", part 1): an interface that is down is a rate of 0, not a dead program.
# On the testbed at 40,000 bit/s, the robot's veth is down when both ends start (a robot booting before its radio
# has associated; with a veth the camp's side has no carrier either): the gateway (--wan-interface VETH, --sensor
# qdisc:VETH) and the camp's `tm-basecamp relay --out` start anyway. tm-robot-sim publishes the paper's workload;
# UP_AT_S seconds in, the link comes up; later it goes down for DOWN_S seconds mid-run and comes back.
# It proves:
#   (a) both ends work once the radio is up, although it was down when they started (Fast DDS's interface
#       whitelist kept none, for the programs' whole life, before): the gateway said the interface was down, and
#       every A published from 2 s after the link came up (time for discovery, about 1.3 s at 40,000 bit/s) until
#       just before it went down reached the camp within its 1 s TTL.
#   (b) while the link is down mid-run nothing is written into the dead interface and counted as forwarded: the
#       gateway forwarded no sample between the link going down and coming back (its on-robot log's
#       forwarded_samples), and per topic what the gateway counts as forwarded is what the camp recorded.
#   (c) when it comes back, the most urgent go first, within a second: the first A the camp records after the
#       link is back (as the kernel reports it up) arrives within 1 s of it, and of the A published from 1 s after
#       it, >= 99 % are on time.
#   (d) nothing unaccounted: per topic, published = the gateway's received = forwarded + dropped, each drop in the
#       on-robot log.
# MODE compact runs the gateway in compact WAN mode (--wan-mode compact; the relay unpacks), where the same must hold.
# START absent: the robot's interface is not there at all when the gateway starts (a USB radio plugged in later, a
# driver loaded late: here the veth goes by another name until UP_AT_S), where the same must hold.
# DOWN_S (default 5) sets the mid-run drop's length. Needs root; skipped (77) otherwise. About 55 s.
#   radio_down_test.sh BIN_DIR [standard|compact] [down|absent]
set -euo pipefail
BIN="${1:?usage: radio_down_test.sh BIN_DIR}"
BIN="$(cd "$BIN" && pwd)"
MODE="${2:-standard}"
START="${3:-down}"
cd "$(dirname "$0")/../.."
# shellcheck source=test/system/system_test_lib.sh
source test/system/system_test_lib.sh
require_netns
require_tools sqlite3

RATE=40000
UP_AT_S=4
DOWN_AT_S=18
DOWN_S=${DOWN_S:-5}  # by hand: longer than the leases (the relay's 60 s, the gateway's 120 s), e.g. DOWN_S=150
PUBLISH_S=$((DOWN_AT_S + DOWN_S + 9))
BOUND_S=$((PUBLISH_S + 30))  # upper bound only, should this script be killed hard
start_testbed "$RATE" radio-down
[ -z "${TGW_TEST_KEEP:-}" ] || trap 'mkdir -p "$TGW_TEST_KEEP" && cp -r "$WORK"/. "$TGW_TEST_KEEP"/; stop_testbed' EXIT
link() { "${tb[@]}" robot ip link set "$veth" "$1"; }

link down
AWAY=radio-absent  # a name in the robot's namespace only
[ "$START" = down ] || "${tb[@]}" robot ip link set "$veth" name "$AWAY"
start_recording_relay "$BOUND_S"
start_paper_gateway "$BOUND_S" --wan-mode "$MODE"

sleep 2
start_paper_publisher "$PUBLISH_S"
sleep "$UP_AT_S"
[ "$START" = down ] || "${tb[@]}" robot ip link set "$AWAY" name "$veth"
link up
up_ns=$(wait_link_up robot "$veth")
echo "link up ${UP_AT_S} s after tm-robot-sim started"
sleep $((DOWN_AT_S - UP_AT_S))
down_ns=$(date +%s%N)
link down
sleep "$DOWN_S"
link up
back_ns=$(wait_link_up robot "$veth")
echo "link down for $(((back_ns - down_ns) / 1000000)) ms from ${DOWN_AT_S} s"

finish_run "$sim_pid" "$gateway_pid" "$record_pid"
show_outputs "$WORK/record.out"

LOG="$WORK/robot-log.db" REC="$WORK/basecamp.db"
q() { camp_query "$1"; }
END_NS=9000000000000000000

echo
echo "== (a) started with the link down"
said_down="$(grep -cE "WAN interface $veth (down|absent): nothing is sent until it is up" "$WORK/gateway.out" || true)"
# The window ends before the link goes down by what an A may wait behind the sample on the wire (a D of 1,016 bytes
# is 0.23 s at 40,000 bit/s) and the link watch's notice: an A published 45 ms before the drop was still queued
# behind one when the link went, and expired (2026-12-06, 1 of 8 runs). Before this edge, the issue asks for all.
EDGE_NS=300000000
read -r a_on a_all <<<"$(a_on_time_between $((up_ns + 2000000000)) $((down_ns - EDGE_NS)))"
first_a_ms="$(q "SELECT printf('%.0f', (MIN(receive_ns) - $up_ns) / 1e6) FROM live_samples WHERE topic = 'telemetry/A'")"
echo "A from 2 s after the link came up until 0.3 s before it went down: $a_on of $a_all on time; the first A at the camp ${first_a_ms:-never} ms after it"
check "the gateway said its WAN interface was down, twice (at start and mid-run)" "a == 2" "$said_down"
check "A from 2 s after the link came up until 0.3 s before it went down: all on time" "b >= 50 && a == b" \
    "$a_on" "$a_all"

echo
echo "== (b) down mid-run"
forwarded_while_down="$(q "SELECT COUNT(*) FROM log.forwarded_samples WHERE forwarded_ns > $down_ns + 200000000
    AND forwarded_ns < $back_ns - 200000000")"
echo "samples the gateway forwarded while the link was down (200 ms in from either edge): $forwarded_while_down"
check "nothing forwarded into the dead interface" "a == 0" "$forwarded_while_down"
# An interface that goes down purges its qdisc: what the gateway wrote in the moment before (still in the tbf's
# queue, which the gateway keeps short) is lost as a radio loses its frames in flight, and no one can count it.
# Those may be missing at the camp: forwarded within IN_FLIGHT_MS before the link went down (1 C of 115 in 1 of 5
# runs, 2026-12-02); nothing else.
IN_FLIGHT_MS=500
for topic in telemetry/A telemetry/B telemetry/C telemetry/D; do
    forwarded="$(awk -v t="$topic" '$1 == t && NF >= 11 { print $3 }' "$WORK/gateway.out")"
    recorded="$(q "SELECT COUNT(DISTINCT source_ns) FROM live_samples WHERE topic = '$topic'")"
    in_flight="$(q "SELECT COUNT(*) FROM log.forwarded_samples WHERE topic = '$topic'
        AND forwarded_ns > $down_ns - ${IN_FLIGHT_MS}000000 AND forwarded_ns <= $down_ns")"
    check "$topic: the gateway's forwarded = the camp's recorded, but for what was in the shaper as the link went down" \
        "b <= a && a - b <= c" "${forwarded:-0}" "$recorded" "$in_flight"
done

echo
echo "== (c) back up"
first_back_ms="$(q "SELECT printf('%.0f', (MIN(receive_ns) - $back_ns) / 1e6) FROM live_samples
    WHERE topic = 'telemetry/A' AND receive_ns >= $back_ns")"
read -r c_on c_all <<<"$(a_on_time_between $((back_ns + 1000000000)) "$END_NS")"
echo "the first A after the link came back: ${first_back_ms:-never} ms after it; A from 1 s after it: $c_on of $c_all on time"
check "the first A after the link came back within 1 s" "a != \"\" && a <= 1000" "${first_back_ms:-}"
check "A from 1 s after the link came back: >= 99 % on time" "b >= 30 && a >= 0.99 * b" "$c_on" "$c_all"

echo
echo "== (d) accounting"
for topic in telemetry/A telemetry/B telemetry/C telemetry/D; do
    read -r received forwarded queued dropped <<<"$(awk -v t="$topic" '$1 == t && NF >= 11 {
        print $2, $3, $4, $5 + $6 + $7 + $8 + $9 + $10 + $11 }' "$WORK/gateway.out")"
    logged="$(q "SELECT COUNT(*) FROM log.dropped_samples WHERE topic = '$topic'")"
    check "$topic: received $received = forwarded $forwarded + dropped $dropped, 0 queued" \
        "a == $forwarded + $dropped && $queued == 0" "$received"
    check "$topic: every drop in the on-robot log" "a == b" "$logged" "$dropped"
done
published="$(awk '$2 == "telemetry/A" { print $5 }' "$WORK/robot.out")"
received_a="$(awk '$1 == "telemetry/A" && NF >= 11 { print $2 }' "$WORK/gateway.out")"
check "telemetry/A: tm-robot-sim's written = the gateway's received" "a == b && a > 0" "${published:-0}" "${received_a:-0}"
exit "$fail"
