#!/usr/bin/env bash
# Mission (issue 45's second target): ten minutes of the paper's workload over the testbed, the radio at 20,000
# bit/s for the first five with a 60 s outage in them, then at 70,000 bit/s for the last five. The gateway runs with
# its defaults (backfill on) and an on-robot log capped at --log-max-mib; the camp's `tm-basecamp relay --out`
# records. What the first half could not carry in time crosses in the second half's spare capacity.
#
# It prints, and checks:
#   - the archive, through `tm-basecamp merge` of the robot's log and the camp's recording: per topic, published
#     (tm-robot-sim's count) against received live, backfilled, only on the robot, lost; >= 99.9 % of the whole
#     received or backfilled, none only on the robot, none twice in the recording; and when the last backfilled row
#     arrived;
#   - live delivery: A on time outside the outage (from 2 s after the link came back) >= 99 %;
#   - the log: the cap was reached and the rows it freed were acknowledged ones (meta's pruned_acknowledged_rows
#     > 0, pruned_dropped_rows = 0: no row the camp lacks was freed), no unacknowledged row left;
#   - the cost: bytes on the link per backfilled sample (the gateway's exit summary) against the same samples live.
#
# --rate-hz HZ (default 2): the workload's rate per stream. At the paper's 5 Hz the workload (87,000 bit/s on the
# wire) exceeds even 70,000 bit/s, so nothing is left over for backfill; at 2 Hz (35,000 bit/s) the five minutes
# at 70,000 bit/s leave about 28,000 for it. --log-max-mib MIB (default 1): the log's cap, which the log passes
# during the second half, once rows are acknowledged. --scale F (default 1) multiplies every duration (0.2 for a
# two-minute trial).
#
# Needs root (network namespaces), sqlite3; exits 77 (skip) without. Not in ctest: 10 min by default.
#   test/bench/backfill_mission.sh BIN_DIR [--rate-hz HZ] [--log-max-mib MIB] [--scale F] [--keep DIR]
set -euo pipefail

RATE_HZ=2
LOG_MIB=1
SCALE=1
KEEP="${TGW_TEST_KEEP:-}"
die_usage() {
    echo "backfill_mission: $*" >&2
    echo "usage: test/bench/backfill_mission.sh BIN_DIR [--rate-hz HZ] [--log-max-mib MIB] [--scale F]" \
        "[--keep DIR]" >&2
    exit 2
}
NUMBER='^[0-9]+([.][0-9]+)?$'
BIN=""
need() { if [ "$2" -lt 2 ] || ! [[ "$3" =~ $4 ]]; then die_usage "$1"; fi; }
while [ $# -gt 0 ]; do
    case "$1" in
        --rate-hz) need "--rate-hz: expected a rate" $# "${2:-}" "$NUMBER"; RATE_HZ="$2"; shift 2 ;;
        --log-max-mib) need "--log-max-mib: expected MiB" $# "${2:-}" "$NUMBER"; LOG_MIB="$2"; shift 2 ;;
        --scale) need "--scale: expected a factor" $# "${2:-}" "$NUMBER"; SCALE="$2"; shift 2 ;;
        --keep) need "--keep: expected a directory" $# "${2:-}" '.'; KEEP="$2"; shift 2 ;;
        -h | --help) awk 'NR > 1 && /^#/ { sub(/^# ?/, ""); print; next } NR > 1 { exit }' "$0"; exit 0 ;;
        -*) die_usage "unknown argument '$1'" ;;
        *) [ -z "$BIN" ] || die_usage "one BIN_DIR only"; BIN="$1"; shift ;;
    esac
done
[ -n "$BIN" ] || die_usage "expected BIN_DIR (a build's bin/)"
BIN="$(cd "$BIN" && pwd)"
[ -n "$KEEP" ] && KEEP="$(mkdir -p "$KEEP" && cd "$KEEP" && pwd)"
cd "$(dirname "$0")/../.."
# shellcheck source=test/system/system_test_lib.sh
source test/system/system_test_lib.sh
require_netns
require_tools sqlite3

seconds() { awk -v s="$1" -v f="$SCALE" 'BEGIN { printf "%.0f", s * f }'; }
SLOW_RATE=20000
FAST_RATE=70000
DOWN_AT_S=$(seconds 120)
DOWN_S=$(seconds 60)
FAST_AT_S=$(seconds 300)
MISSION_S=$(seconds 600)
TAIL_S=30  # after the mission: the most the backlog may still take
BOUND_S=$((MISSION_S + TAIL_S + 40))  # upper bound only, should this script be killed hard

start_testbed "$SLOW_RATE" backfill-mission
[ -z "$KEEP" ] || trap 'cp -r "$WORK"/. "$KEEP"/; stop_testbed' EXIT

start_recording_relay "$BOUND_S"
start_paper_gateway "$BOUND_S" --log-max-mib "$LOG_MIB"
sleep 2
"${tb[@]}" robot "$BIN/tm-robot-sim" --domain 0 --interface 127.0.0.1 --workload paper --rate-hz "$RATE_HZ" \
    --duration "$MISSION_S" --linger 0 --wait-match 10 >"$WORK/robot.out" 2>&1 &
sim_pid=$!
PIDS+=("$sim_pid")
start_ns=$(date +%s%N)
echo "the paper's workload at $RATE_HZ Hz for $MISSION_S s; $SLOW_RATE bit/s, down for $DOWN_S s from $DOWN_AT_S s," \
    "$FAST_RATE bit/s from $FAST_AT_S s; on-robot log capped at $LOG_MIB MiB"

sleep "$DOWN_AT_S"
down_ns=$(date +%s%N)
"${tb[@]}" robot ip link set "$veth" down
sleep "$DOWN_S"
"${tb[@]}" robot ip link set "$veth" up
back_ns=$(wait_link_up robot "$veth")
sleep $((FAST_AT_S - DOWN_AT_S - DOWN_S))
fast_ns=$(date +%s%N)
TGW_TESTBED_ID="$TESTBED_ID" scripts/testbed set-rate "$FAST_RATE" >/dev/null
sim_status=0
wait "$sim_pid" || sim_status=$?
end_ns=$(date +%s%N)

LOG="$WORK/robot-log.db" REC="$WORK/basecamp.db"
q() { camp_query "$1"; }
# The backlog the mission left, if any: a little longer, then stop.
wait_acknowledged "$LOG" "$TAIL_S"
sleep 2
finish_run "$sim_pid" "$gateway_pid" "$record_pid"
show_outputs "$WORK/record.out"

echo
echo "== the archive (tm-basecamp merge of the robot's log and the camp's recording)"
"$BIN/tm-basecamp" merge "$LOG" "$REC" --out "$WORK/mission.db" >"$WORK/merge.out"
total_published=0
total_archived=0
total_only_robot=0
for topic in telemetry/A telemetry/B telemetry/C telemetry/D; do
    published="$(awk -v t="$topic" '$2 == t { print $5 }' "$WORK/robot.out")"
    read -r produced live backfilled only_robot lost <<<"$(archive_fates "$WORK/mission.db" "$topic")"
    echo "$topic: published ${published:-?}; the archive $produced: live $live, backfilled $backfilled," \
        "only on the robot $only_robot, lost $lost"
    total_published=$((total_published + ${published:-0}))
    total_archived=$((total_archived + live + backfilled))
    total_only_robot=$((total_only_robot + only_robot))
done
twice="$(q "SELECT COUNT(*) - COUNT(DISTINCT topic || source_ns) FROM samples WHERE topic LIKE 'telemetry/%'")"
last_ms="$(q "SELECT printf('%.0f', (MAX(receive_ns) - $fast_ns) / 1e6) FROM samples WHERE backfilled")"
check "the camp's archive holds >= 99.9 % of the $total_published published ($total_archived, live or backfilled)" \
    "b > 0 && a >= 0.999 * b" "$total_archived" "$total_published"
check "none only on the robot" "a == 0" "$total_only_robot"
check "none twice in the recording" "a == 0" "${twice:-1}"
echo "the last backfilled sample reached the camp ${last_ms:-never} ms after the link went to $FAST_RATE bit/s" \
    "(the mission ended $(((end_ns - fast_ns) / 1000000)) ms after it)"

echo
echo "== live"
read -r before_on before_all <<<"$(a_on_time_between "$start_ns" "$down_ns")"
read -r after_on after_all <<<"$(a_on_time_between $((back_ns + 2000000000)) "$end_ns")"
check "A on time outside the outage: $((before_on + after_on)) of $((before_all + after_all))" \
    "b > 0 && a >= 0.99 * b" "$((before_on + after_on))" "$((before_all + after_all))"

echo
echo "== the on-robot log"
meta() { sqlite3 -batch -noheader "$LOG" "SELECT COALESCE((SELECT value FROM meta WHERE key = '$1'), 0)"; }
pruned_acked="$(meta pruned_acknowledged_rows)"
pruned_forwarded="$(meta pruned_forwarded_rows)"
pruned_unacked="$(meta pruned_dropped_rows)"
left="$(unacknowledged_rows "$LOG")"
echo "rows freed at the cap: $pruned_acked acknowledged, $pruned_forwarded forwarded, $pruned_unacked the camp" \
    "lacked; $left unacknowledged left; $(du -k "$LOG" | cut -f1) KiB on disk"
check "the cap was reached, and it freed acknowledged rows" "a > 0" "$pruned_acked"
check "no row the camp lacked was freed" "a == 0" "$pruned_unacked"
check "every row acknowledged" "a == 0" "$left"

echo
echo "== the cost"
grep '^backfill on tgw/backfill' "$WORK/gateway.out" || echo "(the gateway said nothing of backfill)"
sed -nE 's/^wire bytes per forwarded sample.*: (.*)/live, per sample as the budget charged it: \1/p' "$WORK/gateway.out"
[ "$sim_status" = 0 ] || echo "tm-robot-sim exited $sim_status"
exit "$fail"
