#!/usr/bin/env bash
# tm-basecamp stats and status, run as programs the way an operator runs them, against a known pattern: a gateway
# on loopback (1 Mbit/s, nothing held back, a recorder reading from the start) bridges tm-robot-sim's
# stats/ten_hz (100 B at 10 Hz, TTL 1 s) and stats/two_hz (500 B at 2 Hz, TTL 5 s). stats --once must show those
# rates, the bit/s of what tm-robot-sim says it serialized, everything within its TTL and nothing logged on the
# robot, also when started before the robot publishes; status --once, taken after publishing ended, must show per
# topic the counts of the gateway's own exit summary.
set -euo pipefail
BIN=$1
ROBOT=$((200 + $$ % 15 * 2))  # 200..228: above the in-process tests' domains, apart from parallel runs
WAN=$((ROBOT + 1))
work=$(mktemp -d)
pids=()
cleanup() {
    for pid in "${pids[@]}"; do kill "$pid" 2>/dev/null || true; done
    wait 2>/dev/null || true
    rm -rf "$work"
}
trap cleanup EXIT
fail=0
check() {  # DESCRIPTION CONDITION(awk expression over a, b) A B
    if awk -v a="$3" -v b="$4" "BEGIN { exit !($2) }"; then
        echo "ok: $1 ($3)"
    else
        echo "FAIL: $1: got $3, expected $2 with b=$4"
        fail=1
    fi
}

printf 'ten stats/ten_hz 100 1 10\ntwo stats/two_hz 500 5 2\n' >"$work/workload"
# The camp as it runs: the topics declared in a --qos file, so their WAN writers exist from the start, and a
# recorder that reads them before the robot publishes. Otherwise the gateway would hold the first samples for a
# reader (it sends nothing to no one), and stats, joining, would see them come in a burst.
profile() {  # TOPIC TTL_S
    printf '<data_writer profile_name="%s"><qos><reliability><kind>BEST_EFFORT</kind></reliability>' "$1"
    printf '<lifespan><duration><sec>%s</sec><nanosec>0</nanosec></duration></lifespan></qos>' "$2"
    printf '<topic><kind>NO_KEY</kind><dataType>tgw::idl::PaperMessage</dataType></topic></data_writer>\n'
}
{
    echo '<?xml version="1.0" encoding="UTF-8"?>'
    echo '<dds xmlns="http://www.eprosima.com/XMLSchemas/fastRTPS_Profiles"><profiles>'
    profile stats/ten_hz 1
    profile stats/two_hz 5
    echo '</profiles></dds>'
} >"$work/qos.xml"
# The recorder starts first, so it is the WAN domain's first participant on this host and the gateway is not:
# stats and status must still find the gateway at once (when they announced themselves to the first
# participant's port alone, they heard of the gateway only at its next announcement, up to 20 s later, and
# stats measured its window after the robot had stopped; CI, 2026-11-26).
"$BIN/tm-basecamp" record --domain "$WAN" --peer 127.0.0.1 --out "$work/camp.db" --duration 40 \
    >"$work/record.out" 2>&1 &
pids+=("$!")
sleep 1
# Stopped with SIGINT once status has run: a fixed duration left status, after stats' discovery and window,
# too little of the gateway's life.
"$BIN/telemetry-gateway" --robot-domain "$ROBOT" --wan-domain "$WAN" --wan-peer 127.0.0.1 --sensor fixed:1000000 \
    --qos "$work/qos.xml" --duration 60 >"$work/gateway.out" 2>&1 &
gateway=$!
pids+=("$gateway")
# A stats --once started before the robot publishes: its window must open on the robot's first sample, not on the
# gateway's status (and WAN writers) that come first (a 20 s window so opened missed the last 3 s of a camera's run).
"$BIN/tm-basecamp" stats --domain "$WAN" --peer 127.0.0.1 --once --window 5 >"$work/stats-early.out" 2>&1 &
early=$!
pids+=("$early")
sleep 3
"$BIN/tm-robot-sim" --domain "$ROBOT" --workload "$work/workload" --duration 9 >"$work/sim.out" 2>&1 &
sim=$!
pids+=("$sim")
sleep 2
"$BIN/tm-basecamp" stats --domain "$WAN" --peer 127.0.0.1 --once --window 5 >"$work/stats.out"
cat "$work/stats.out"
wait "$sim"
cat "$work/sim.out"
wait "$early" || true
cat "$work/stats-early.out"
early_total=$(awk '$1 == "stats/ten_hz" { print $NF }' "$work/stats-early.out")
check "stats --once started before the robot: stats/ten_hz's samples in its 5 s window (10 Hz)" "a >= 40" \
    "${early_total:-none}" 0
for topic in stats/ten_hz stats/two_hz; do
    hz=$(awk -v t="$topic" '$1 == t { print $2 }' "$work/stats.out")
    bps=$(awk -v t="$topic" '$1 == t { print $3 }' "$work/stats.out")
    in_ttl=$(awk -v t="$topic" '$1 == t { print $7 }' "$work/stats.out")
    logged=$(awk -v t="$topic" '$1 == t { print $8 }' "$work/stats.out")
    payload=$(awk -v t="$topic" '$2 == t { print $(NF - 1) }' "$work/sim.out")
    rate=$([ "$topic" = stats/ten_hz ] && echo 10 || echo 2)
    check "$topic: Hz" "a >= b * 0.9 && a <= b * 1.1" "${hz:-none}" "$rate"
    check "$topic: bit/s against ${payload:-?} B x 8 x $rate Hz" "a >= b * 0.85 && a <= b * 1.15" "${bps:-none}" \
        "$((${payload:-0} * 8 * rate))"
    check "$topic: % within TTL" "a == 100" "${in_ttl:-none}" 0
    check "$topic: logged on the robot, per the gateway's status" "a == 0" "${logged:-none}" 0
done

# Publishing has ended: the next status has the final counts.
sleep 2
"$BIN/tm-basecamp" status --domain "$WAN" --peer 127.0.0.1 --once --timeout 20 >"$work/status.out"
cat "$work/status.out"
kill -INT "$gateway"
wait "$gateway" || true
cat "$work/gateway.out"
for topic in stats/ten_hz stats/two_hz; do
    # status: topic ttl_s queued queued_B received forwarded ...; the exit summary: topic received forwarded ...
    status_received=$(awk -v t="$topic" '$1 == t { print $5 }' "$work/status.out")
    status_forwarded=$(awk -v t="$topic" '$1 == t { print $6 }' "$work/status.out")
    summary_received=$(awk -v t="$topic" '$1 == t { print $2; exit }' "$work/gateway.out")
    summary_forwarded=$(awk -v t="$topic" '$1 == t { print $3; exit }' "$work/gateway.out")
    check "$topic: received in the status = in the exit summary" "a == b && a > 0" "${status_received:-none}" \
        "${summary_received:-none}"
    check "$topic: forwarded in the status = in the exit summary" "a == b && a > 0" "${status_forwarded:-none}" \
        "${summary_forwarded:-none}"
done
exit "$fail"
