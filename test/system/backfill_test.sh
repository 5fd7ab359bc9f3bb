#!/usr/bin/env bash
# System test (issue 45, "Backfill"): the base camp's archive gets every sample the robot produced.
# On the testbed, tm-robot-sim publishes the paper's workload for PUBLISH_S seconds over a link of 20,000 bit/s, far
# less than the workload needs: most B, C and D miss their TTL and stay in the on-robot log. Then the link idles at
# 100,000 bit/s for IDLE_S seconds. The camp's `tm-basecamp relay --out` records.
# It proves, with MODE on (the gateway's default):
#   (a) live delivery is what it is without backfill: A >= 99 % on time (run MODE off beside it to compare);
#   (b) the archive is whole: >= 99.9 % of the samples published are in the camp's recording, live or backfilled,
#       each once;
#   (c) nothing backfilled reached the camp's live domain as a live sample, and the rows the camp stored are
#       acknowledged in the robot's log;
#   (d) `tm-basecamp merge` counts each sample once, the dropped ones as backfilled, none only on the robot.
# MODE off runs the same with --no-backfill and checks (a) and that nothing was backfilled, printing what the
# archive holds. WAN compact runs the gateway in compact WAN mode (the relay unpacks), where the same must hold.
# Needs root; skipped (77) otherwise. About 80 s with IDLE_S=40.
#   backfill_test.sh BIN_DIR [on|off] [standard|compact]
set -euo pipefail
BIN="${1:?usage: backfill_test.sh BIN_DIR [on|off]}"
BIN="$(cd "$BIN" && pwd)"
MODE="${2:-on}"
WAN="${3:-standard}"
cd "$(dirname "$0")/../.."
# shellcheck source=test/system/system_test_lib.sh
source test/system/system_test_lib.sh
require_netns
require_tools sqlite3

LIVE_RATE=20000
IDLE_RATE=100000
PUBLISH_S=30
IDLE_S=${IDLE_S:-60}
BOUND_S=$((PUBLISH_S + IDLE_S + 40))  # upper bound only, should this script be killed hard
start_testbed "$LIVE_RATE" backfill
[ -z "${TGW_TEST_KEEP:-}" ] || trap 'mkdir -p "$TGW_TEST_KEEP" && cp -r "$WORK"/. "$TGW_TEST_KEEP"/; stop_testbed' EXIT

start_recording_relay "$BOUND_S"
backfill=()
[ "$MODE" = on ] || backfill=(--no-backfill)
start_paper_gateway "$BOUND_S" --wan-mode "$WAN" "${backfill[@]}"
sleep 2
start_paper_publisher "$PUBLISH_S"
wait "$sim_pid" || true
idle_ns=$(date +%s%N)
TGW_TESTBED_ID="$TESTBED_ID" scripts/testbed set-rate "$IDLE_RATE" >/dev/null
echo "published for ${PUBLISH_S} s at $LIVE_RATE bit/s; the link idles at $IDLE_RATE bit/s for ${IDLE_S} s"
sleep "$IDLE_S"
finish_run "$sim_pid" "$gateway_pid" "$record_pid"
show_outputs "$WORK/record.out"

LOG="$WORK/robot-log.db" REC="$WORK/basecamp.db"
q() { camp_query "$1"; }

echo
echo "== (a) live"
read -r a_on a_all <<<"$(a_on_time_between 0 "$idle_ns")"
echo "A on time: $a_on of $a_all"
check "A: >= 99 % on time" "b >= 140 && a >= 0.99 * b" "$a_on" "$a_all"

echo
echo "== (b) the archive"
published="$(awk '$2 ~ /^telemetry\// { n += $5 } END { print n + 0 }' "$WORK/robot.out")"
for topic in telemetry/A telemetry/B telemetry/C telemetry/D; do
    q "SELECT '$topic', SUM(backfilled = 0), SUM(backfilled = 1), COUNT(DISTINCT source_ns) FROM samples
        WHERE topic = '$topic'" | awk -F'|' '{ printf "%s: %s live, %s backfilled, %s distinct\n", $1, $2, $3, $4 }'
done
archived="$(q "SELECT COUNT(*) FROM (SELECT DISTINCT topic, source_ns FROM samples WHERE topic LIKE 'telemetry/%')")"
twice="$(q "SELECT COUNT(*) FROM (SELECT topic, source_ns FROM samples WHERE topic LIKE 'telemetry/%'
    GROUP BY topic, source_ns HAVING COUNT(*) > 1)")"
echo "in the camp's recording: $archived of $published published; $twice stored twice"
if [ "$MODE" = off ]; then
    check "--no-backfill: nothing backfilled" "a == 0" "$(q "SELECT COUNT(*) FROM samples WHERE backfilled")"
    exit "$fail"
fi
check "the archive holds >= 99.9 % of what was published" "b >= 590 && a >= 0.999 * b" "$archived" "$published"
check "each sample stored once (live or backfilled, never both)" "a == 0" "$twice"

echo
echo "== (c) backfill's own accounting"
backfilled="$(q "SELECT COUNT(*) FROM samples WHERE backfilled = 1")"
acked="$(q "SELECT COUNT(*) FROM log.dropped_samples WHERE acked_ns IS NOT NULL")"
logged="$(q "SELECT COUNT(*) FROM log.dropped_samples")"
sends="$(q "SELECT COALESCE(SUM(sends), 0) FROM log.dropped_samples")"
echo "backfilled $backfilled of $logged logged rows; $acked acknowledged; $sends sends"
check "every logged row reached the camp" "a == b && b > 20" "$backfilled" "$logged"
check "the robot's log has every row the camp stored acknowledged" "a == b" "$acked" "$backfilled"
relayed_live="$(awk '$1 ~ /^telemetry\// && $3 == "samples" && $4 == "relayed" { n += $2 } END { print n + 0 }' \
    "$WORK/record.out")"
live_rows="$(q "SELECT COUNT(*) FROM samples WHERE backfilled = 0 AND topic LIKE 'telemetry/%'")"
check "the camp's live domain got only the live samples" "a == b" "$relayed_live" "$live_rows"

echo
echo "== (d) the mission archive (tm-basecamp merge)"
"$BIN/tm-basecamp" merge "$LOG" "$REC" --out "$WORK/mission.db" | tail -4
read -r produced _ _ only_robot lost <<<"$(archive_fates "$WORK/mission.db" 'telemetry/%')"
echo "archive: $produced samples, $only_robot only on the robot, $lost lost on the link"
check "the archive holds each sample published once, none only on the robot" "a == c && b == 0" \
    "$produced" "$only_robot" "$published"
exit "$fail"
