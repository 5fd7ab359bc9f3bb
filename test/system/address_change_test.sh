#!/usr/bin/env bash
# System test: the robot's WAN interface has no IPv4 address when the gateway starts (DHCP not done), and the camp's
# name (the gateway's --wan-peer basecamp.tgw) does not resolve yet; a second into publishing it does (the robot
# namespace's /etc/hosts, as ip netns exec shows it), 5 s in the interface gets an address, and it changes mid-run (a new lease, a mesh radio's), the link staying up (issue 44's second part). Over
# the testbed's 40,000 bit/s tbf, the paper's workload, the camp's relay given the robot's name as its peer
# (rover.tgw, in the camp namespace's /etc/hosts, changed to the new address with it): the gateway starts with the robot's veth bare; 4 s into publishing it gets 10.77.0.1; 16 s in it loses that
# and gets 10.77.0.5 (the camp routes to it). Each time the gateway makes its WAN participant anew on the address:
# A from 2 s after the first address until the change is on time but for one; the camp hears the robot again
# within 5 s of the change (its first A after it), A is >= 99 % on time from 5 s after it; nothing is forwarded
# while the veth has no address; per topic the camp recorded what the gateway forwarded (but for what was written
# in the moment the old address went, before the gateway heard of it), and every sample is accounted for. Needs root; skipped (77) otherwise.
#   address_change_test.sh BIN_DIR
set -euo pipefail
BIN="${1:?usage: address_change_test.sh BIN_DIR}"
BIN="$(cd "$BIN" && pwd)"
cd "$(dirname "$0")/../.."
# shellcheck source=test/system/system_test_lib.sh
source test/system/system_test_lib.sh
require_netns
require_tools sqlite3

RATE=40000
NAME_AT_S=1
ADDRESS_AT_S=5
CHANGE_AT_S=16
PUBLISH_S=32
NEW_ADDR=10.77.0.5
BOUND_S=$((PUBLISH_S + 30))  # upper bound only, should this script be killed hard
start_testbed "$RATE" address-change
camp_veth="$(TGW_TESTBED_ID="$TESTBED_ID" scripts/testbed info basecamp-veth)"
# ip netns exec shows a namespace's own /etc/netns/NAME/hosts as /etc/hosts: the camp's name, once written there.
robot_etc="/etc/netns/$(TGW_TESTBED_ID="$TESTBED_ID" scripts/testbed info robot-ns)"
mkdir -p "$robot_etc"
printf '127.0.0.1 localhost\n' >"$robot_etc/hosts"
# The camp knows the robot by its name too (relay --peer rover.tgw): its address, then the new one.
camp_etc="/etc/netns/$(TGW_TESTBED_ID="$TESTBED_ID" scripts/testbed info basecamp-ns)"
mkdir -p "$camp_etc"
printf '127.0.0.1 localhost\n%s rover.tgw\n' "$robot_addr" >"$camp_etc/hosts"
# shellcheck disable=SC2317  # called by the EXIT trap
forget_hosts() {
    rm -rf "$robot_etc" "$camp_etc"
    rmdir --ignore-fail-on-non-empty /etc/netns 2>/dev/null || true
}
trap 'forget_hosts; stop_testbed' EXIT
[ -z "${TGW_TEST_KEEP:-}" ] ||
    trap 'forget_hosts; mkdir -p "$TGW_TEST_KEEP" && cp -r "$WORK"/. "$TGW_TEST_KEEP"/; stop_testbed' EXIT

"${tb[@]}" robot ip addr flush dev "$veth"
"${tb[@]}" basecamp "$BIN/tm-basecamp" relay --domain 1 --peer rover.tgw --interface "$basecamp_addr" \
    --local-domain 7 --out "$WORK/basecamp.db" --duration "$BOUND_S" >"$WORK/record.out" 2>&1 &
record_pid=$!
PIDS+=("$record_pid")
WAN_PEER=basecamp.tgw start_paper_gateway "$BOUND_S"

sleep 2
start_paper_publisher "$PUBLISH_S"
sleep "$NAME_AT_S"
printf '%s basecamp.tgw\n' "$basecamp_addr" >>"$robot_etc/hosts"  # the same file: the bind mount shows it
sleep $((ADDRESS_AT_S - NAME_AT_S))
address_ns=$(date +%s%N)
"${tb[@]}" robot ip addr add "$robot_addr/30" dev "$veth"
echo "robot's veth given $robot_addr ${ADDRESS_AT_S} s after tm-robot-sim started"
sleep $((CHANGE_AT_S - ADDRESS_AT_S))
# When each end hears of the change: samples written before may be lost with the old address, or with the relay's
# old participant.
stamp_line "$WORK/gateway.out" "has $NEW_ADDR now, not $robot_addr" "$WORK/gateway-heard.ns"
stamp_line "$WORK/record.out" "is $NEW_ADDR now: the relay's WAN participant is made anew" "$WORK/relay-remade.ns"
move_address robot "$veth" "$robot_addr" "$NEW_ADDR" "$camp_veth"
# The same file: the bind mount shows it (a name server's record updated, as a DHCP server with DNS does).
printf '127.0.0.1 localhost\n%s rover.tgw\n' "$NEW_ADDR" >"$camp_etc/hosts"

finish_run "$sim_pid" "$gateway_pid" "$record_pid"
show_outputs "$WORK/record.out"

LOG="$WORK/robot-log.db" REC="$WORK/basecamp.db"
q() { camp_query "$1"; }

echo
echo "== no address at start"
forwarded_bare="$(q "SELECT COUNT(*) FROM log.forwarded_samples WHERE forwarded_ns < $address_ns - 200000000")"
first_a_ms="$(q "SELECT printf('%.0f', (MIN(receive_ns) - $address_ns) / 1e6) FROM live_samples WHERE topic = 'telemetry/A'")"
read -r a_on a_all <<<"$(a_on_time_between $((address_ns + 2000000000)) "$change_ns")"
echo "forwarded while the veth had no address: $forwarded_bare; the first A at the camp ${first_a_ms:-never} ms" \
    "after the address came; A from 2 s after it until the change: $a_on of $a_all on time"
check "the gateway looked basecamp.tgw up and found $basecamp_addr later" "a == 1" \
    "$(grep -c "wan-peer basecamp.tgw is $basecamp_addr now: the WAN participant is made anew" "$WORK/gateway.out" || true)"
check "the gateway said its WAN interface had no address (at start; again between the change's two steps)" "a >= 1" \
    "$(grep -c "WAN interface $veth up without an IPv4 address: nothing is sent until it is up with one" \
        "$WORK/gateway.out" || true)"
check "the gateway made its WAN participant anew on $robot_addr when it came" "a == 1" \
    "$(grep -c "has $robot_addr now, not 127.0.0.1: the WAN participant is made anew on it" "$WORK/gateway.out" || true)"
check "nothing forwarded while the veth had no address" "a == 0" "$forwarded_bare"
check "A from 2 s after the address came until the change: all but one on time" "b >= 40 && a >= b - 1" \
    "$a_on" "$a_all"

echo
echo "== the address changes"
first_after_ms="$(q "SELECT printf('%.0f', (MIN(receive_ns) - $change_ns) / 1e6) FROM live_samples
    WHERE topic = 'telemetry/A' AND source_ns >= $change_ns")"
from_ns=$((change_ns + 5000000000))
published="$(q "SELECT COUNT(*) FROM (SELECT source_time_ns FROM log.forwarded_samples WHERE topic = 'telemetry/A'
    UNION ALL SELECT source_time_ns FROM log.dropped_samples WHERE topic = 'telemetry/A')
    WHERE source_time_ns >= $from_ns")"
on_time="$(q "SELECT COUNT(*) FROM (SELECT source_ns, MIN(receive_ns) AS receive_ns FROM live_samples
    WHERE topic = 'telemetry/A' AND source_ns >= $from_ns GROUP BY source_ns)
    WHERE receive_ns - source_ns <= 1000000000")"
echo "the first A published after the change reached the camp ${first_after_ms:-never} ms after it;" \
    "A from 5 s after it: $on_time of $published on time"
check "the gateway made its WAN participant anew on $NEW_ADDR" "a == 1" \
    "$(grep -c "has $NEW_ADDR now, not $robot_addr: the WAN participant is made anew on it" "$WORK/gateway.out" || true)"
check "the camp heard the robot again within 5 s of the change" "a != \"\" && a <= 5000" "${first_after_ms:-}"
check "the relay looked rover.tgw up again and was made anew announcing to $NEW_ADDR" "a == 1" \
    "$(grep -c -- "--peer rover.tgw is $NEW_ADDR now: the relay's WAN participant is made anew" "$WORK/record.out" || true)"
check "A from 5 s after the change: >= 99 % on time" "b >= 50 && a >= 0.99 * b" "$on_time" "$published"

echo
echo "== accounting"
gateway_heard_ns="$(cat "$WORK/gateway-heard.ns" 2>/dev/null || echo "$change_ns")"
relay_remade_ns="$(cat "$WORK/relay-remade.ns" 2>/dev/null || echo "$change_ns")"
echo "the gateway heard of the change $(((gateway_heard_ns - change_ns) / 1000000)) ms after it, the relay was" \
    "made anew $(((relay_remade_ns - change_ns) / 1000000)) ms after it"
for topic in telemetry/A telemetry/B telemetry/C telemetry/D; do
    forwarded="$(awk -v t="$topic" '$1 == t && NF >= 11 { print $3 }' "$WORK/gateway.out")"
    recorded="$(q "SELECT COUNT(DISTINCT source_ns) FROM live_samples WHERE topic = '$topic'")"
    # Lost in flight: written between the old address going and the gateway hearing of it, or up to the shaper's
    # 1 s of queue before the relay's old participant went.
    in_flight="$(q "SELECT COUNT(*) FROM log.forwarded_samples WHERE topic = '$topic'
        AND ((forwarded_ns >= $change_ns - 100000000 AND forwarded_ns < $gateway_heard_ns + 100000000)
          OR (forwarded_ns >= $relay_remade_ns - 1100000000 AND forwarded_ns < $relay_remade_ns + 100000000))")"
    said="$topic: the camp recorded what the gateway forwarded ($recorded of ${forwarded:-0}; $in_flight written"
    check "$said as the address went or the relay was made anew)" "a <= b && a >= b - $in_flight" "$recorded" \
        "${forwarded:-0}"
    read -r received forwarded queued dropped <<<"$(awk -v t="$topic" '$1 == t && NF >= 11 {
        print $2, $3, $4, $5 + $6 + $7 + $8 + $9 + $10 + $11 }' "$WORK/gateway.out")"
    check "$topic: received $received = forwarded $forwarded + dropped $dropped, 0 queued" \
        "a == $forwarded + $dropped && $queued == 0" "$received"
done
exit "$fail"
