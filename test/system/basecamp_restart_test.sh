#!/usr/bin/env bash
# System test (issue 20, "Faults: the base camp restarts mid-run"). On the testbed at 20,000 bit/s the gateway
# forwards the paper's workload from tm-robot-sim to tm-basecamp record. After RUN_BEFORE_S of publishing the
# base camp dies without a word (SIGKILL, as a power cut or a reboot would leave it), and DOWN_S later a new
# tm-basecamp record starts in its place, with a new DDS participant and a new recording. It proves:
#   (a) the gateway rediscovers the new base camp and resumes within 5 s: the first robot sample recorded by the
#       new base camp arrives at most RESUME_MAX_S after it started;
#   (b) from then on A is on time again: of the A samples published >= RESUME_MAX_S after the restart, >= 99 %
#       were recorded within their 1 s TTL;
#   (c) per topic, nothing unaccounted: tm-robot-sim's written = the gateway's received (one at most lost on the
#       robot's loopback, the open robot-side defect) = forwarded + queued + dropped, queued 0 at the end, each
#       drop reason's count = the on-robot log's rows of that reason, forwarded = the log's forwarded_samples.
# What the gateway forwarded while the base camp was dead and not yet known to be (its lease has not run out:
# nothing on the WAN says a participant is gone) reached no one; the test prints how many.
# Needs root; skipped (77) otherwise. About 60 s.
#   basecamp_restart_test.sh BIN_DIR [sigkill|sigterm]
set -euo pipefail
BIN="${1:?usage: basecamp_restart_test.sh BIN_DIR [sigkill|sigterm]}"
BIN="$(cd "$BIN" && pwd)"
HOW="${2:-sigkill}"
cd "$(dirname "$0")/../.."
# shellcheck source=test/system/system_test_lib.sh
source test/system/system_test_lib.sh
require_netns
require_tools sqlite3
case "$HOW" in
    sigkill) SIGNAL=KILL ;;
    sigterm) SIGNAL=TERM ;;
    *) echo "basecamp_restart_test.sh: unknown way to stop the base camp '$HOW' (sigkill or sigterm)" >&2; exit 2 ;;
esac

RATE=20000
RUN_BEFORE_S=15
DOWN_S=5
RUN_AFTER_S=25
PUBLISH_S=$((RUN_BEFORE_S + DOWN_S + RUN_AFTER_S))
RESUME_MAX_S=5
BOUND_S=$((PUBLISH_S + 40))  # upper bound only, should this script be killed hard
start_testbed "$RATE" restart
# TGW_TEST_KEEP=DIR keeps the recordings, the on-robot log and the programs' output there.
[ -z "${TGW_TEST_KEEP:-}" ] || trap 'mkdir -p "$TGW_TEST_KEEP" && cp -r "$WORK"/. "$TGW_TEST_KEEP"/; stop_testbed' EXIT

record() {  # record N: a base camp recording into $WORK/basecampN.db
    "${tb[@]}" basecamp "$BIN/tm-basecamp" record --domain 1 --peer "$robot_addr" --interface "$basecamp_addr" \
        --out "$WORK/basecamp$1.db" --duration "$BOUND_S" >"$WORK/record$1.out" 2>&1 &
    PIDS+=("$!")
}
record 1
first_record_pid=$!
start_paper_gateway "$BOUND_S"

sleep 2
start_paper_publisher "$PUBLISH_S"

sleep "$RUN_BEFORE_S"
kill -"$SIGNAL" "$first_record_pid"
wait "$first_record_pid" 2>/dev/null || true
killed_ns=$(date +%s%N)
echo "the base camp stopped by SIG$SIGNAL"
sleep "$DOWN_S"
restart_ns=$(date +%s%N)
record 2
second_record_pid=$!
echo "a new base camp started $(((restart_ns - killed_ns) / 1000000)) ms later"

finish_run "$sim_pid" "$gateway_pid" "$second_record_pid"

show_outputs "$WORK/record2.out"

LOG="$WORK/robot-log.db" REC="$WORK/basecamp2.db"
q() { camp_query "$1"; }

# (a) resumption.
first_ms="$(q "SELECT printf('%.0f', (MIN(receive_ns) - $restart_ns) / 1e6) FROM live_samples
    WHERE topic LIKE 'telemetry/%'")"
echo
echo "== (a) the first robot sample at the new base camp ${first_ms:-never} ms after it started"
check "the new base camp got a robot sample within $RESUME_MAX_S s of its start" \
    "a != \"\" && a <= $((RESUME_MAX_S * 1000))" "${first_ms:-}"

# (b) A once resumed.
since=$((restart_ns + RESUME_MAX_S * 1000000000))
a_all="$(q "SELECT COUNT(*) FROM (SELECT source_time_ns FROM log.forwarded_samples WHERE topic = 'telemetry/A'
                                   UNION ALL SELECT source_time_ns FROM log.dropped_samples WHERE topic = 'telemetry/A')
            WHERE source_time_ns >= $since")"
a_on_time="$(q "SELECT COUNT(*) FROM (SELECT source_ns, MIN(receive_ns) AS receive_ns FROM live_samples
    WHERE topic = 'telemetry/A' AND source_ns >= $since GROUP BY source_ns) WHERE receive_ns - source_ns <= 1000000000")"
echo "== (b) A published >= $RESUME_MAX_S s after the restart: $a_on_time of $a_all on time at the new base camp"
check "A after the restart: some" "a > 0" "$a_all"
check "A after the restart: >= 99 % on time" "a >= 0.99 * b" "${a_on_time:-0}" "$a_all"

# (c) accounting per topic, and what went to the dead base camp.
echo
echo "== (c) accounting per topic"
printf '%-12s %9s %8s %9s %6s %7s %9s %8s %21s\n' topic published gw_recv forwarded queued dropped no_reader \
    recorded "forwarded while down"
for t in A B C D; do
    topic="telemetry/$t"
    published="$(awk -v t="$topic" '$2 == t { print $5 }' "$WORK/robot.out")"
    # topic received forwarded queued expired doomed evicted oversize shutdown write_failed no_reader ttl...
    read -r recv fwd queued ex dm ev os sd wf nr <<<"$(awk -v t="$topic" '$1 == t && NF >= 11 {
        print $2, $3, $4, $5, $6, $7, $8, $9, $10, $11 }' "$WORK/gateway.out")"
    dropped=$((${ex:-0} + ${dm:-0} + ${ev:-0} + ${os:-0} + ${sd:-0} + ${wf:-0} + ${nr:-0}))
    log_fwd="$(q "SELECT COUNT(*) FROM log.forwarded_samples WHERE topic = '$topic'")"
    log_dropped="$(q "SELECT COUNT(*) FROM log.dropped_samples WHERE topic = '$topic'")"
    log_no_reader="$(q "SELECT COUNT(*) FROM log.dropped_samples WHERE topic = '$topic' AND reason = 'no_reader'")"
    recorded="$(q "SELECT COUNT(DISTINCT source_ns) FROM live_samples WHERE topic = '$topic'")"
    while_down="$(q "SELECT COUNT(*) FROM log.forwarded_samples WHERE topic = '$topic'
        AND forwarded_ns >= $killed_ns AND forwarded_ns < $restart_ns")"
    printf '%-12s %9s %8s %9s %6s %7s %9s %8s %21s\n' "$topic" "${published:-?}" "${recv:-?}" "${fwd:-?}" \
        "${queued:-?}" "$dropped" "${nr:-?}" "$recorded" "$while_down"
    check "$topic: the gateway received all tm-robot-sim wrote, but one at most" "a >= b - 1 && a <= b && a > 0" \
        "${recv:-0}" "${published:--1}"
    check "$topic: received = forwarded + queued + dropped" "a == b" "${recv:-0}" "$((${fwd:-0} + ${queued:-0} + dropped))"
    check "$topic: nothing still queued at the end" "a == 0" "${queued:--1}"
    check "$topic: every drop is a row of the on-robot log" "a == b" "$log_dropped" "$dropped"
    check "$topic: every no_reader drop is a no_reader row" "a == b" "$log_no_reader" "${nr:--1}"
    check "$topic: forwarded = the log's forwarded_samples rows" "a == b" "$log_fwd" "${fwd:--1}"
done
check "tm-robot-sim exited 0" "a == 0" "$sim_status"
check "the gateway exited 0" "a == 0" "$gateway_status"
exit "$fail"
