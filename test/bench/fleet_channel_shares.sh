#!/usr/bin/env bash
# One radio channel shared by two robots (issue 21, part 3), three ways of splitting it, on the fleet testbed
# (scripts/testbed up RATE --robots 2: both robots behind one router whose way out to the base camp is the tbf
# shaper). rover1 has hazards to send: two topics of 41-byte samples at 5 Hz with a TTL of 1 s (about 19,000 bit/s
# on the wire); rover2 has bulk: 1,016-byte samples at 5 Hz with a TTL of 20 s (about 48,000 bit/s). The base camp
# runs tm-basecamp relay, which records what arrives. Each way runs on a fresh testbed for --duration S:
#   none     each gateway budgets for the whole channel (--sensor fixed:RATE), as if the radio were its own;
#   equal    each budgets for half of it (--sensor fixed:RATE/2): equal fixed shares;
#   grants   each senses the whole channel, and the relay grants shares (--channel-rate RATE, --channel-grants);
#   overstated  the same, but the base camp takes the channel for twice what it is (--channel-rate 2*RATE, or
#            --claimed BPS): a radio whose rate fell since it was configured;
#   measured the same, with the base camp measuring the channel (--measure-channel, --channel-rate its bound).
# Printed per way: rover1's hazards on time at the base camp (of those published), and rover2's bulk received.
# Needs root; not in ctest (about 1 min a way). WAYS="none equal grants" by default; WAYS="grants overstated
# measured" compares the measure.
# --rate-drop BPS@S: the channel's rate falls to BPS S seconds after the robots start publishing (scripts/testbed
# set-rate): the base camp's --channel-rate is then the rate it had.
#   test/bench/fleet_channel_shares.sh BIN_DIR [--duration S] [--rate BPS] [--claimed BPS] [--rate-drop BPS@S]
set -euo pipefail
BIN=$(cd "$1" && pwd)
shift
DURATION=30
RATE=30000
CLAIMED=""
DROP=""
while [ $# -gt 0 ]; do
    case "$1" in
        --duration) DURATION=$2; shift 2 ;;
        --rate) RATE=$2; shift 2 ;;
        --claimed) CLAIMED=$2; shift 2 ;;
        --rate-drop) DROP=$2; shift 2 ;;
        *) echo "fleet_channel_shares.sh: unknown argument '$1'" >&2; exit 2 ;;
    esac
done
CLAIMED=${CLAIMED:-$((2 * RATE))}
ROOT=$(cd "$(dirname "$0")/../.." && pwd)
cd "$ROOT"
[ "$(id -u)" -eq 0 ] || { echo "needs root (network namespaces)"; exit 77; }
export TGW_TESTBED_ID="cs$(($$ % 100000))"
work=$(mktemp -d)
pids=()
cleanup() {
    for pid in "${pids[@]}"; do kill "$pid" 2>/dev/null || true; done
    wait 2>/dev/null || true
    scripts/testbed down 2>/dev/null || true
    if [ -n "${KEEP:-}" ]; then echo "kept $work"; else rm -rf "$work"; fi
}
trap cleanup EXIT
printf 'H1 hazard/left 41 1 5\nH2 hazard/right 41 1 5\n' >"$work/rover1.workload"
printf 'D bulk/scan 1016 20 5\n' >"$work/rover2.workload"

run() {  # WAY
    local way=$1 dir="$work/$1" k sensor grant_flags=() relay_flags=()
    mkdir -p "$dir"
    scripts/testbed up "$RATE" --robots 2 >/dev/null
    local camp robot_addr
    camp=$(scripts/testbed info basecamp-addr)
    sensor="fixed:$RATE"
    [ "$way" = equal ] && sensor="fixed:$((RATE / 2))"
    case "$way" in
        grants) relay_flags=(--channel-rate "$RATE") ;;
        overstated) relay_flags=(--channel-rate "$CLAIMED") ;;
        measured) relay_flags=(--channel-rate "$CLAIMED" --measure-channel) ;;
    esac
    [ ${#relay_flags[@]} -gt 0 ] && grant_flags=(--channel-grants)
    local peers=()
    for k in 1 2; do peers+=(--peer "$(scripts/testbed info "robot$k-addr")"); done
    scripts/testbed exec basecamp "$BIN/tm-basecamp" relay --domain 1 --interface "$camp" "${peers[@]}" \
        --local-domain 2 --local-interface 127.0.0.1 "${relay_flags[@]}" --out "$dir/camp.db" \
        >"$dir/relay.out" 2>&1 &
    local relay=$!
    pids+=("$relay")
    local gateways=() sims=()
    for k in 1 2; do
        robot_addr=$(scripts/testbed info "robot$k-addr")
        scripts/testbed exec "robot$k" "$BIN/telemetry-gateway" --robot-domain 0 --wan-domain 1 \
            --wan-interface "$robot_addr" --wan-peer "$camp" --wan-peer-participants 1 --robot-name "rover$k" \
            --sensor "$sensor" "${grant_flags[@]}" --log "$dir/rover$k.db" >"$dir/gateway$k.out" 2>&1 &
        gateways+=("$!")
        pids+=("$!")
    done
    sleep 5
    for k in 1 2; do
        scripts/testbed exec "robot$k" "$BIN/tm-robot-sim" --domain 0 --interface 127.0.0.1 \
            --workload "$work/rover$k.workload" --duration "$DURATION" --linger 0 --wait-match 10 \
            >"$dir/sim$k.out" 2>&1 &
        sims+=("$!")
        pids+=("$!")
    done
    if [ -n "$DROP" ]; then
        sleep "${DROP#*@}"
        scripts/testbed set-rate "${DROP%@*}" >/dev/null
    fi
    for pid in "${sims[@]}"; do wait "$pid" || true; done
    sleep 2
    for pid in "${gateways[@]}"; do kill -TERM "$pid" 2>/dev/null || true; done
    for pid in "${gateways[@]}"; do wait "$pid" || true; done
    kill -TERM "$relay" 2>/dev/null || true
    wait "$relay" 2>/dev/null || true
    scripts/testbed down >/dev/null 2>&1 || true

    local offered="" topic published
    for topic in hazard/left hazard/right; do
        published=$(awk -v t="$topic" '$2 == t { print $5 }' "$dir/sim1.out")
        offered+=" --offered rover1/$topic=${published:-0}"
    done
    published=$(awk '$2 == "bulk/scan" { print $5 }' "$dir/sim2.out")
    # shellcheck disable=SC2086
    "$BIN/tm-basecamp" report "$dir/camp.db" $offered --offered "rover2/bulk/scan=${published:-0}" \
        >"$dir/report.txt" 2>&1 || true
    # report's row: topic ttl_s offered received on_time %on_time mean_ms sd_ms max_ms, and robot for a fleet
    awk -v way="$way" '
        (NF == 9 || NF == 10) && $1 ~ /^rover1\/hazard\// { off += $3; on += $5 }
        (NF == 9 || NF == 10) && $1 == "rover2/bulk/scan" { bulk_off = $3; bulk_rx = $4 }
        END { printf "%-7s rover1 hazards on time: %d of %d (%.1f %%); rover2 bulk received: %d of %d\n",
                     way, on, off, off ? 100 * on / off : 0, bulk_rx, bulk_off }' "$dir/report.txt"
    grep -h "last grant\|channel measured" "$dir/relay.out" | sed "s/^/$way  /" || true
}

echo "fleet_channel_shares: 2 robots, channel $RATE bit/s${DROP:+ falling to ${DROP%@*} after ${DROP#*@} s} ($CLAIMED claimed where overstated or measured), $DURATION s each"
for way in ${WAYS:-none equal grants}; do
    run "$way"
done
