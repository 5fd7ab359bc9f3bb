#!/usr/bin/env bash
# Discovery traffic per robot on a shared, shaped link (issue 21: "with and without the server, for 1, 3 and 6
# robots"). For each robot count N and each way of discovery, a fresh testbed (scripts/testbed up RATE --robots N:
# N robot namespaces behind one router whose way out to the base camp is the tbf shaper) runs for --duration S:
#   peers   each gateway announces to the base camp (--wan-peer BASECAMP --wan-peer-participants 1), the relay
#           to every robot (--peer ROBOT_K ...);
#   server  fast-discovery-server at the base camp, the gateways its clients (--wan-discovery-server), the relay
#           a super client (--discovery-server).
# Each robot runs telemetry-gateway with qos/paper_workload.xml (its four topics declared, so their WAN writers
# exist from the start) and no publisher: what crosses the link is discovery and its reliability traffic alone,
# start-up included. The base camp runs tm-basecamp relay (receiver reports off: --report-period 0). Printed per
# run: the bytes and packets the shaper sent robots -> base camp, and the base camp's veth sent the other way,
# in all and per robot, as bit/s over the run. Needs root and fastdds-tools; not in ctest (about 7 min).
#   test/bench/fleet_discovery_traffic.sh BIN_DIR [--duration S] [--rate BPS] [--robots "1 3 6"]
set -euo pipefail
BIN=$(cd "$1" && pwd)
shift
DURATION=60
RATE=60000
ROBOT_COUNTS="1 3 6"
while [ $# -gt 0 ]; do
    case "$1" in
        --duration) DURATION=$2; shift 2 ;;
        --rate) RATE=$2; shift 2 ;;
        --robots) ROBOT_COUNTS=$2; shift 2 ;;
        *) echo "fleet_discovery_traffic.sh: unknown argument '$1'" >&2; exit 2 ;;
    esac
done
ROOT=$(cd "$(dirname "$0")/../.." && pwd)
cd "$ROOT"
[ "$(id -u)" -eq 0 ] || { echo "needs root (network namespaces)"; exit 77; }
command -v fast-discovery-server >/dev/null || { echo "needs fast-discovery-server (fastdds-tools)"; exit 77; }
export TGW_TESTBED_ID="fd$(($$ % 100000))"
work=$(mktemp -d)
pids=()
cleanup() {
    for pid in "${pids[@]}"; do kill "$pid" 2>/dev/null || true; done
    wait 2>/dev/null || true
    scripts/testbed down 2>/dev/null || true
    rm -rf "$work"
}
trap cleanup EXIT
tb() { scripts/testbed "$@"; }
CAMP=10.77.0.6

run() {  # ROBOTS MODE
    local n=$1 mode=$2 k
    pids=()
    tb up "$RATE" --robots "$n" >/dev/null 2>&1
    local camp_flags=()
    if [ "$mode" = server ]; then
        tb exec basecamp fast-discovery-server -i 0 -l "$CAMP" -p 11811 >"$work/server.out" 2>&1 &
        pids+=("$!")
        camp_flags=(--discovery-server "$CAMP:11811")
    else
        for ((k = 1; k <= n; k++)); do camp_flags+=(--peer "$(tb info "robot$k-addr")"); done
    fi
    # The camp's own domain on its loopback: its discovery would otherwise go out on the veth too.
    tb exec basecamp "$BIN/tm-basecamp" relay --domain 1 --interface "$CAMP" --local-domain 2 \
        --local-interface 127.0.0.1 --report-period 0 \
        "${camp_flags[@]}" --duration $((DURATION + 5)) >"$work/relay.out" 2>&1 &
    pids+=("$!")
    for ((k = 1; k <= n; k++)); do
        local addr gateway_flags
        addr=$(tb info "robot$k-addr")
        if [ "$mode" = server ]; then
            gateway_flags=(--wan-discovery-server "$CAMP:11811")
        else
            gateway_flags=(--wan-peer "$CAMP" --wan-peer-participants 1)
        fi
        tb exec "robot$k" "$BIN/telemetry-gateway" --robot-domain 0 --wan-domain 1 --wan-interface "$addr" \
            "${gateway_flags[@]}" --robot-name "rover$k" --sensor "fixed:$((RATE / n))" --status-period 0 \
            --qos qos/paper_workload.xml --no-log --duration "$DURATION" >"$work/gateway$k.out" 2>&1 &
        pids+=("$!")
    done
    sleep "$DURATION"
    local shaped reverse
    shaped=$(tb stats | awk '/Sent/ { print $2, $4; exit }')
    reverse=$(ip -n "$(tb info basecamp-ns)" -s link show dev "$(tb info basecamp-veth)" |
        awk '/TX:/ { getline; print $1, $2; exit }')
    for pid in "${pids[@]}"; do kill "$pid" 2>/dev/null || true; done
    wait 2>/dev/null || true
    tb down >/dev/null 2>&1
    local matched
    matched=$(grep -c "^  rover" "$work/relay.out" || true)
    set -- $shaped $reverse
    awk -v n="$n" -v mode="$mode" -v d="$DURATION" -v sb="$1" -v sp="$2" -v rb="$3" -v rp="$4" -v m="$matched" \
        'BEGIN { printf "| %d | %s | %d (%d) | %.0f | %d (%d) | %.0f | %d |\n", n, mode, sb, sp, sb * 8 / d / n, rb, rp, rb * 8 / d / n, m }'
}

echo "fleet_discovery_traffic: ${DURATION} s per run, link ${RATE} bit/s shared, $(date -u +%FT%TZ), $(git rev-parse --short HEAD)"
echo "| robots | discovery | robots -> camp: bytes (packets) | bit/s per robot | camp -> robots: bytes (packets) | bit/s per robot | topics the relay took |"
echo "|---:|---|---:|---:|---:|---:|---:|"
for n in $ROBOT_COUNTS; do
    for mode in peers server; do
        run "$n" "$mode"
    done
done
