#!/usr/bin/env bash
# Large samples on a fast link (issue 48): camera frames of --size BYTES (default 1 MiB) at --rate-hz (30) for
# --duration S (20) from the robot to the base camp over the testbed's veth shaped at --link-rate BPS (1 Gbit/s),
# first direct (tm-robot-sim on the robot's address, tm-basecamp stats at the camp, both Fast DDS with their
# defaults: UDP unicast peers), then through the gateway (tm-robot-sim on the robot's loopback, telemetry-gateway
# --wan-max-datagram 65500 with a fixed sensor at the link's rate, the same tm-basecamp stats on the WAN domain).
# The publisher is reliable, Lifespan 1 s, history of a second's frames (tm-robot-sim's), as a camera driver's.
#
# --transient-local: the publisher's writer is transient local, as Fast DDS's default writer (a camera driver left at
# its defaults): the gateway then gives the topic a latched lane, which keeps the last frame for late joiners.
#
# --latest-only: the gateway's rule for the topic is latest_only (a newer frame replaces the one still waiting, which
# goes to the on-robot log as superseded), as a camera's should be when frames may ask for more than the link.
#
# Prints each path's tm-basecamp stats row (Hz, bit/s, mean and p99 transmission time, % within TTL), the gateway's
# summary row for the topic (received, forwarded, logged by reason), the on-robot log's rows by reason, and its memory: VmRSS before the publisher started and its peak
# (VmHWM). Needs sqlite3 for the log's reasons.
#
# Needs root (network namespaces); exits 77 (skip) without. Not in ctest: about 75 s.
#   test/bench/large_samples_veth.sh BIN_DIR [--size BYTES] [--rate-hz HZ] [--duration S] [--link-rate BPS]
#                                            [--transient-local] [--latest-only] [--keep DIR]
set -euo pipefail

SIZE=1048576
RATE_HZ=30
DURATION=20
LINK_RATE=1000000000
LATEST_ONLY=""
SIM_DURABILITY=()
KEEP_DIR="${TGW_TEST_KEEP:-}"
die_usage() {
    echo "large_samples_veth: $*" >&2
    echo "usage: test/bench/large_samples_veth.sh BIN_DIR [--size BYTES] [--rate-hz HZ] [--duration S]" \
        "[--link-rate BPS] [--transient-local] [--latest-only] [--keep DIR]" >&2
    exit 2
}
need() { if [ "$2" -lt 2 ] || ! [[ "$3" =~ $4 ]]; then die_usage "$1"; fi; }
BIN=""
while [ $# -gt 0 ]; do
    case "$1" in
        --size) need "--size: expected bytes" $# "${2:-}" '^[1-9][0-9]*$'; SIZE="$2"; shift 2 ;;
        --rate-hz) need "--rate-hz: expected samples/s" $# "${2:-}" '^[1-9][0-9]*$'; RATE_HZ="$2"; shift 2 ;;
        --duration) need "--duration: expected whole seconds" $# "${2:-}" '^[1-9][0-9]*$'; DURATION="$2"; shift 2 ;;
        --link-rate) need "--link-rate: expected bit/s" $# "${2:-}" '^[1-9][0-9]*$'; LINK_RATE="$2"; shift 2 ;;
        --transient-local) SIM_DURABILITY=(--transient-local); shift ;;
        --latest-only) LATEST_ONLY=1; shift ;;
        --keep) need "--keep: expected a directory" $# "${2:-}" '.'; KEEP_DIR="$2"; shift 2 ;;
        -h | --help) awk 'NR > 1 && /^#/ { sub(/^# ?/, ""); print; next } NR > 1 { exit }' "$0"; exit 0 ;;
        -*) die_usage "unknown argument '$1'" ;;
        *) [ -z "$BIN" ] || die_usage "one BIN_DIR only"; BIN="$1"; shift ;;
    esac
done
[ -n "$BIN" ] || die_usage "expected BIN_DIR (a build's bin/)"
BIN="$(cd "$BIN" && pwd)"
cd "$(dirname "$0")/../.."
# shellcheck source=test/system/system_test_lib.sh
source test/system/system_test_lib.sh
require_netns
require_tools sqlite3
for program in telemetry-gateway tm-robot-sim tm-basecamp; do
    [ -x "$BIN/$program" ] || { echo "large_samples_veth: $BIN/$program is missing" >&2; exit 2; }
done

# A bucket of 4 MiB: at 1 Gbit/s tbf's one-frame default would cost a timer per frame.
start_testbed "$LINK_RATE" large-samples --burst 4194304
echo "camera camera/frames $SIZE 1 $RATE_HZ" >"$WORK/workload"
gateway_config=()
if [ -n "$LATEST_ONLY" ]; then
    printf 'topics:\n  - match: camera/frames\n    latest_only: true\n' >"$WORK/gateway.yaml"
    gateway_config=(--config "$WORK/gateway.yaml")
fi
STATS_S=$((DURATION + 15))

# stats_row FILE: the camera topic's row of tm-basecamp stats --once.
stats_row() { awk '$1 ~ /frames$/ { print; exit }' "$1"; }
# kib PID FIELD: FIELD of /proc/PID/status (VmRSS, VmHWM) in KiB.
kib() { awk -v f="$2:" '$1 == f { print $2 }' "/proc/$1/status"; }

# 1. Direct: the publisher's participant knows the camp by address, the camp's the robot.
"${tb[@]}" basecamp "$BIN/tm-basecamp" stats --domain 0 --peer "$robot_addr" --once --window "$DURATION" \
    --duration "$STATS_S" >"$WORK/direct.stats" 2>&1 &
direct_stats=$!
PIDS+=("$direct_stats")
"${tb[@]}" robot "$BIN/tm-robot-sim" --domain 0 --peer "$basecamp_addr" --workload "$WORK/workload" \
    --duration "$DURATION" --linger 1 --wait-match 10 "${SIM_DURABILITY[@]+"${SIM_DURABILITY[@]}"}" >"$WORK/direct.sim" 2>&1 || { cat "$WORK/direct.sim"; exit 1; }
wait "$direct_stats" || true

# 2. Through the gateway.
"${tb[@]}" robot "$BIN/telemetry-gateway" --robot-domain 0 --wan-domain 1 --wan-peer "$basecamp_addr" \
    --wan-interface "$veth" --wan-peer-participants 1 --sensor "fixed:$LINK_RATE" --wan-max-datagram 65500 \
    --log "$WORK/robot-log.db" --duration "$((STATS_S + 5))" "${gateway_config[@]}" >"$WORK/gateway.out" 2>&1 &
gateway=$!
PIDS+=("$gateway")
# Its window opens on the first frame and stays open 2 s after the publisher stops: the frames still queued then
# (on a link they overload) go out.
"${tb[@]}" basecamp "$BIN/tm-basecamp" stats --domain 1 --peer "$robot_addr" --once --window "$((DURATION + 2))" \
    --duration "$STATS_S" >"$WORK/via.stats" 2>&1 &
via_stats=$!
PIDS+=("$via_stats")
# The gateway's memory before the publisher, 3 s after its start.
sleep 3
rss_start="$(kib "$gateway" VmRSS)"
"${tb[@]}" robot "$BIN/tm-robot-sim" --domain 0 --interface 127.0.0.1 --workload "$WORK/workload" \
    --duration "$DURATION" --linger 1 --wait-match 10 "${SIM_DURABILITY[@]+"${SIM_DURABILITY[@]}"}" >"$WORK/via.sim" 2>&1 &
via_sim=$!
PIDS+=("$via_sim")
wait "$via_sim" || true
hwm="$(kib "$gateway" VmHWM)"
rss_end="$(kib "$gateway" VmRSS)"
wait "$via_stats" || true
kill -TERM "$gateway" 2>/dev/null || true  # its summary: received, forwarded and logged per topic
wait "$gateway" || true

direct="$(stats_row "$WORK/direct.stats")"
via="$(stats_row "$WORK/via.stats")"
echo "large samples: $SIZE B at $RATE_HZ Hz for $DURATION s over a veth shaped at $LINK_RATE bit/s (tbf)${LATEST_ONLY:+, latest_only}"
head -n 3 "$WORK/via.stats" | grep -i "topic" || true
echo "direct:      ${direct:-(nothing received)}"
echo "via gateway: ${via:-(nothing received)}"
reasons="$(sqlite3 -batch -noheader "$WORK/robot-log.db" \
    "SELECT reason || ' ' || COUNT(*) FROM dropped_samples GROUP BY reason" 2>/dev/null | paste -sd ',' - | sed 's/,/, /g' || true)"
echo "on-robot log: ${reasons:-no frame}"
awk '$1 == "topic" && $2 == "received" || $1 ~ /frames$/ && NF >= 11 { print "gateway: " $0 }' "$WORK/gateway.out"
echo "gateway memory: VmRSS ${rss_start} KiB before the publisher started, peak ${hwm} KiB, ${rss_end} KiB at the end"
if [ -n "$KEEP_DIR" ]; then
    mkdir -p "$KEEP_DIR" && cp -r "$WORK/." "$KEEP_DIR/"
    echo "outputs kept in $KEEP_DIR"
fi
[ -n "$direct" ] && [ -n "$via" ]
