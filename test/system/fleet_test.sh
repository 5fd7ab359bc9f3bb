#!/usr/bin/env bash
# A fleet on the testbed (issue 21, parts 1 and 2): two robot namespaces behind one router whose way out to the
# base camp is shaped at 60,000 bit/s (scripts/testbed --robots 2). Debian's fast-discovery-server runs at the base
# camp; each robot's telemetry-gateway is its client, bound to the robot's own address (rover1 in standard WAN
# mode, rover2 in compact mode, each budgeting half the link), and bridges tm-robot-sim's paper workload; the base
# camp's relay, a super client bound to the camp's address, records what it takes off the WAN. Nobody names a
# peer. Checks, per robot: its topics arrive under its name, A is at least 99 % on time, and every sample is
# accounted for (tm-basecamp report with the robot's on-robot log).
set -euo pipefail
BIN=$1
cd "$(dirname "$0")/../.."
source test/system/system_test_lib.sh
require_netns
require_tools fast-discovery-server
start_testbed 60000 fleet --robots 2
DURATION=20
WARMUP=15
server="$basecamp_addr:11811"

"${tb[@]}" basecamp fast-discovery-server -i 0 -l "$basecamp_addr" -p 11811 >"$WORK/server.out" 2>&1 &
PIDS+=("$!")
"${tb[@]}" basecamp "$BIN/tm-basecamp" relay --domain 1 --interface "$basecamp_addr" --discovery-server "$server" \
    --local-domain 2 --local-interface 127.0.0.1 --out "$WORK/camp.db" >"$WORK/relay.out" 2>&1 &
relay=$!
PIDS+=("$relay")
gateways=()
sims=()
for k in 1 2; do
    addr=$(TGW_TESTBED_ID="$TESTBED_ID" scripts/testbed info "robot$k-addr")
    mode=standard
    [ "$k" -eq 2 ] && mode=compact
    "${tb[@]}" "robot$k" "$BIN/telemetry-gateway" --robot-domain 0 --wan-domain 1 --wan-interface "$addr" \
        --wan-discovery-server "$server" --robot-name "rover$k" --wan-mode "$mode" --sensor fixed:30000 \
        --robot-interface 127.0.0.1 \
        --qos qos/paper_workload.xml --log "$WORK/rover$k.db" >"$WORK/gateway$k.out" 2>&1 &
    gateways+=("$!")
    PIDS+=("$!")
done
# The topics are declared (qos/paper_workload.xml), so their WAN writers exist from the start; discovery through
# the server crosses the shaped link (about 20 kB per gateway, measured in the first runs): let it settle, or the
# first samples wait for a reader and expire, as they would for a robot that publishes before its camp listens.
sleep "$WARMUP"
for k in 1 2; do
    "${tb[@]}" "robot$k" "$BIN/tm-robot-sim" --domain 0 --interface 127.0.0.1 --workload paper --rate-hz 5 \
        --duration "$DURATION" --linger 0 --wait-match 10 >"$WORK/sim$k.out" 2>&1 &
    sims+=("$!")
    PIDS+=("$!")
done
for pid in "${sims[@]}"; do wait "$pid" || true; done
finish_fleet "$relay" "${gateways[@]}"

for k in 1 2; do
    published=$(awk '$2 == "telemetry/A" { print $5 }' "$WORK/sim$k.out")
    "$BIN/tm-basecamp" report "$WORK/camp.db" --robot-log "$WORK/rover$k.db" --offered "rover$k/telemetry/A=${published:-0}" \
        >"$WORK/report$k.txt" 2>&1 || true
    # report's accounting row: topic offered received on_time late expired ... unaccounted matched
    row=$(awk -v t="rover$k/telemetry/A" '$1 == t && NF == 17 { print; exit }' "$WORK/report$k.txt")
    read -r _ offered received on_time _ <<<"${row:-x 0 0 0}"
    unaccounted=$(awk -v t="rover$k/telemetry/A" '$1 == t && NF == 17 { print $16; exit }' "$WORK/report$k.txt")
    check "rover$k: tm-robot-sim published telemetry/A ($published)" "a >= 90" "${published:-0}"
    check "rover$k/telemetry/A at the base camp: $on_time of $offered on time" "b > 0 && a >= 0.99 * b" "$on_time" "$offered"
    check "rover$k/telemetry/A: nothing unaccounted" "a == 0" "${unaccounted:-1}"
    # D (TTL 20 s) mostly waits for the link past the run's end in standard mode: not checked.
    for type in B C; do
        check "rover$k/telemetry/$type reached the base camp under the robot's name" "a > 0" \
            "$(awk -v t="rover$k/telemetry/$type" '$1 == t && (NF == 9 || NF == 10) { print $4; exit }' "$WORK/report$k.txt")"
    done
done
# Each bundle leaves once, and the budget charged what the robot sent: with the server at the base camp, a gateway
# whose transport also listened on its own loopback sent every message a second time from there (nothing of it
# reached the link) and charged its budget for both (base::listen_for_a_same_host_server).
rover2_veth=$(TGW_TESTBED_ID="$TESTBED_ID" scripts/testbed info robot2-veth)
sent_bytes=$("${tb[@]}" robot2 cat "/sys/class/net/$rover2_veth/statistics/tx_bytes")
bundles=$(sed -n 's/^WAN bundles: \([0-9]*\),.*/\1/p' "$WORK/gateway2.out")
bundle_wire=$(sed -n 's/^WAN bundles: .* and \([0-9]*\) on the wire on average.*/\1/p' "$WORK/gateway2.out")
messages=$(sed -n "s/^WAN datagrams: \([0-9]*\) samples' messages.*/\1/p" "$WORK/gateway2.out")
unscheduled=$(sed -n 's/^WAN traffic outside the schedule ([^)]*): \([0-9]*\) bytes.*/\1/p' "$WORK/gateway2.out")
# The participant's announcements leave in the schedule, charged as they go (RepairDesk::hold_announcement).
announced=$(sed -n 's/^announcements of the WAN participant, in the schedule: .* sent (\([0-9]*\) bytes).*/\1/p' \
    "$WORK/gateway2.out")
charged=$(( ${bundles:-0} * ${bundle_wire:-0} + ${unscheduled:-0} + ${announced:-0} ))
check "rover2's gateway wrote each bundle once (${messages:-?} messages for ${bundles:-?} bundles)" "b > 0 && a == b" \
    "${messages:-0}" "${bundles:-0}"
check "rover2's gateway charged its budget what it sent (${charged} bytes charged, ${sent_bytes:-?} sent)" \
    "b > 0 && a >= 0.95 * b && a <= 1.05 * b" "$charged" "${sent_bytes:-0}"

if [ "$fail" -ne 0 ]; then
    for f in server.out relay.out gateway1.out gateway2.out sim1.out sim2.out report1.txt report2.txt tc.txt; do
        echo "--- $f"
        cat "$WORK/$f"
    done
fi
exit "$fail"
