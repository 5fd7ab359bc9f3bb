#!/usr/bin/env bash
# Soak (issue 20, "Faults: ten minutes at 1,000 bit/s"): the paper's workload (tm-robot-sim --workload paper
# --rate-hz 5: 55,560 bit/s of data, 59,000 of serialized payload) through the gateway for --duration S over the
# testbed shaped at --rate BPS, with the gateway's default queue memory cap unless --queue-memory is given. The
# set-up is outage_test.sh's: tm-basecamp record at the base camp, telemetry-gateway --sensor qdisc:VETH --qos
# qos/paper_workload.xml with its on-robot log in the work directory, and the gateway's resident memory (VmRSS,
# with RssAnon, RssFile and RssShmem) and the log's size on disk sampled every 0.5 s.
#
# It prints VmRSS at start (the last sample before the first sample reached the gateway: discovery done, nothing
# queued yet), 1 min later, its peak, at the end of publishing, and its growth (a least-squares line, KiB/min)
# over the last 80 % of the publishing time (the last 8 min of 10) and over the last half; the cap; the queue's
# peak payload (rebuilt from the on-robot log: each sample is in the queue from its arrival to when it was logged
# or forwarded); the on-robot log's size on disk; per topic, published = received = forwarded + queued + dropped
# by reason, each reason = its rows in the log; and A's on-time figure at the base camp.
#
# "Resident memory stays under the cap plus a fixed overhead": the overhead is VmRSS at start plus --margin-kib
# (default 4096: SQLite's page cache, which the log leaves at SQLite's default of 2,000 KiB and which fills as the
# log grows, plus 2 MiB for the allocator and Fast DDS's history pools; measured on 2026-11-25 in four 10 min
# runs at 1,000 bit/s: VmRSS rose 2,180 to 2,308 KiB above its start, all of it RssAnon, in the first 4 min,
# then by 12 KiB at most). Exits 1 if the peak exceeds cap + overhead, or start + margin + the queue's peak
# payload (tighter while the queue stays far below the cap), if VmRSS still grew faster than --max-slope
# KIB_PER_MIN (default 16: a leak of 14 bytes per sample received) over the last half of the publishing time
# (the last 8 min also hold that first rise: 43 to 57 KiB/min there, 1.2 to 2.3 over the last 5 min), or if any
# topic's accounting does not hold.
#
# Needs root (network namespaces), sqlite3 and python3; exits 77 (skip) without. Not in ctest: 10 min by default.
#   test/bench/low_rate_soak.sh BIN_DIR [--duration S] [--rate BPS] [--queue-memory MIB] [--margin-kib KIB]
#                                       [--max-slope KIB_PER_MIN] [--discover-rate BPS] [--keep DIR]
# --discover-rate BPS (default 20,000): the shaper's rate for the 15 s before publishing, while the base camp and
# the gateway discover each other; then --rate for the whole workload. 0: --rate from the start (at 1,000 bit/s
# the base camp then matched no topic in 10 min, and every sample went to the log as 'no_reader').
# --keep DIR (or TGW_TEST_KEEP=DIR) keeps the recording, the on-robot log, the samples and the programs' output.
set -euo pipefail

DURATION=600
RATE=1000
QUEUE_MIB=""
MARGIN_KIB=4096
MAX_SLOPE_KIB_MIN=16
DISCOVER_RATE=20000
DISCOVER_S=15
KEEP="${TGW_TEST_KEEP:-}"
die_usage() {
    echo "low_rate_soak: $*" >&2
    echo "usage: test/bench/low_rate_soak.sh BIN_DIR [--duration S] [--rate BPS] [--queue-memory MIB]" \
        "[--margin-kib KIB] [--max-slope KIB_PER_MIN] [--discover-rate BPS] [--keep DIR]" >&2
    exit 2
}
NUMBER='^[0-9]+([.][0-9]+)?$'
BIN=""
need() { if [ "$2" -lt 2 ] || ! [[ "$3" =~ $4 ]]; then die_usage "$1"; fi; }
while [ $# -gt 0 ]; do
    case "$1" in
        --duration) need "--duration: expected whole seconds" $# "${2:-}" '^[0-9]+$'; DURATION="$2"; shift 2 ;;
        --rate) need "--rate: expected bit/s" $# "${2:-}" '^[1-9][0-9]*$'; RATE="$2"; shift 2 ;;
        --queue-memory) need "--queue-memory: expected MiB" $# "${2:-}" "$NUMBER"; QUEUE_MIB="$2"; shift 2 ;;
        --margin-kib) need "--margin-kib: expected KiB" $# "${2:-}" '^[0-9]+$'; MARGIN_KIB="$2"; shift 2 ;;
        --max-slope) need "--max-slope: expected KiB/min" $# "${2:-}" "$NUMBER"; MAX_SLOPE_KIB_MIN="$2"; shift 2 ;;
        --discover-rate) need "--discover-rate: expected bit/s" $# "${2:-}" '^[0-9]+$'; DISCOVER_RATE="$2"
            shift 2 ;;
        --keep) need "--keep: expected a directory" $# "${2:-}" '.'; KEEP="$2"; shift 2 ;;
        -h | --help) awk 'NR > 1 && /^#/ { sub(/^# ?/, ""); print; next } NR > 1 { exit }' "$0"; exit 0 ;;
        -*) die_usage "unknown argument '$1'" ;;
        *) [ -z "$BIN" ] || die_usage "one BIN_DIR only"; BIN="$1"; shift ;;
    esac
done
[ -n "$BIN" ] || die_usage "expected BIN_DIR (a build's bin/)"
[ "$DURATION" -ge 60 ] || die_usage "--duration: at least 60 s (the figures include VmRSS after 1 min)"
BIN="$(cd "$BIN" && pwd)"
[ -n "$KEEP" ] && KEEP="$(mkdir -p "$KEEP" && cd "$KEEP" && pwd)"
cd "$(dirname "$0")/../.."
# shellcheck source=test/system/system_test_lib.sh
source test/system/system_test_lib.sh
require_netns
require_tools sqlite3 python3
for program in telemetry-gateway tm-robot-sim tm-basecamp; do
    [ -x "$BIN/$program" ] || { echo "low_rate_soak: $BIN/$program is missing" >&2; exit 2; }
done

# The cap: the gateway's own default (from its --help), unless given.
if [ -z "$QUEUE_MIB" ]; then
    cap_arg=()
    CAP_MIB="$("$BIN/telemetry-gateway" --help | sed -nE 's/^ *--queue-memory [A-Z:]*=([0-9.]+).*/\1/p')"
    [ -n "$CAP_MIB" ] || { echo "low_rate_soak: no default in telemetry-gateway --help's --queue-memory" >&2; exit 2; }
    cap_note="the gateway's default"
else
    cap_arg=(--queue-memory "$QUEUE_MIB")
    CAP_MIB="$QUEUE_MIB"
    cap_note="--queue-memory $QUEUE_MIB"
fi
CAP_KIB="$(awk -v m="$CAP_MIB" 'BEGIN { printf "%d", m * 1024 }')"
# Upper bound only, should this script be killed hard: discovery, publishing, the drain of the last frame.
BOUND_S=$((DISCOVER_S + DURATION + 90))
echo "== low_rate_soak: $(date -u '+%Y-%m-%d %H:%M:%S UTC'), $DURATION s at $RATE bit/s, queue cap $CAP_MIB MiB" \
    "($cap_note); binaries in $BIN, built $(date -u -r "$BIN/telemetry-gateway" '+%Y-%m-%d %H:%M UTC')"

if [ "$DISCOVER_RATE" -gt 0 ]; then
    start_testbed "$DISCOVER_RATE" soak
else
    start_testbed "$RATE" soak
fi
[ -z "$KEEP" ] || trap 'cp -r "$WORK"/. "$KEEP"/; stop_testbed' EXIT
LOG="$WORK/robot-log.db"
REC="$WORK/basecamp.db"

"${tb[@]}" basecamp "$BIN/tm-basecamp" record --domain 1 --peer "$robot_addr" --interface "$basecamp_addr" \
    --out "$REC" --duration "$BOUND_S" >"$WORK/record.out" 2>&1 &
record_pid=$!
PIDS+=("$record_pid")
"${tb[@]}" robot "$BIN/telemetry-gateway" --robot-domain 0 --wan-domain 1 --wan-peer "$basecamp_addr" \
    --wan-interface "$veth" --sensor "qdisc:$veth" --qos qos/paper_workload.xml --wan-peer-participants 1 \
    "${cap_arg[@]+"${cap_arg[@]}"}" --log "$LOG" --duration "$BOUND_S" >"$WORK/gateway.out" 2>&1 &
gateway_pid=$!
PIDS+=("$gateway_pid")

# Every 0.5 s: "ns VmRSS RssAnon RssFile RssShmem log_bytes" (KiB, and the log's files in bytes). The PID is the
# gateway itself: testbed exec execs.
sample_rss() {
    local rss log_bytes
    while kill -0 "$gateway_pid" 2>/dev/null; do
        rss="$(awk '/^(VmRSS|RssAnon|RssFile|RssShmem):/ { printf " %s", $2 }' "/proc/$gateway_pid/status" \
            2>/dev/null || true)"
        log_bytes="$(stat -c %s "$LOG" "$LOG-wal" 2>/dev/null | awk '{ s += $1 } END { print s + 0 }' || true)"
        [ -z "$rss" ] || echo "$(date +%s%N)$rss $log_bytes"
        sleep 0.5
    done >"$WORK/rss.txt"
}
sample_rss &
PIDS+=("$!")

if [ "$DISCOVER_RATE" -gt 0 ]; then
    # Discovery at a usable rate first (the robot starts beside the base camp, then the radio degrades): at
    # 1,000 bit/s from the start the base camp matched no topic in 10 min (every sample logged 'no_reader').
    sleep "$DISCOVER_S"
    TGW_TESTBED_ID="$TESTBED_ID" scripts/testbed set-rate "$RATE"
    echo "discovery: $DISCOVER_S s at $DISCOVER_RATE bit/s, then the shaper at $RATE bit/s; publishing starts"
else
    sleep 2
fi
"${tb[@]}" robot "$BIN/tm-robot-sim" --domain 0 --interface 127.0.0.1 --workload paper --rate-hz 5 \
    --duration "$DURATION" --linger 0 --wait-match 10 >"$WORK/robot.out" 2>&1 &
sim_pid=$!
PIDS+=("$sim_pid")
sim_started_ns=$(date +%s%N)
# A line a minute, so that a 10 min run shows it is alive.
minute=0
while kill -0 "$sim_pid" 2>/dev/null; do
    sleep 1
    now_ns=$(date +%s%N)
    if [ $(((now_ns - sim_started_ns) / 60000000000)) -gt "$minute" ]; then
        minute=$((minute + 1))
        read -r _ rss _ _ _ log_bytes < <(tail -n 1 "$WORK/rss.txt") || true
        echo "  $minute min: gateway VmRSS ${rss:-?} KiB, on-robot log ${log_bytes:-?} bytes"
    fi
done
sim_status=0
wait "$sim_pid" || sim_status=$?
publish_end_ns=$(date +%s%N)

# The gateway logs what is still queued ('shutdown'). Then the recorder waits for the shaper to drain, 15 s at
# most: its queue holds at most rate x 1 s + the 1,600-byte burst, 13.8 s at 1,000 bit/s (one frame of D alone
# takes 9.7 s). The backlog need not reach 0: in a trial 5 packets stayed 30 s after the gateway had stopped.
sleep 2
kill -TERM "$gateway_pid" 2>/dev/null || true
gateway_status=0
wait "$gateway_pid" || gateway_status=$?
for _ in $(seq 15); do
    backlog="$(TGW_TESTBED_ID="$TESTBED_ID" scripts/testbed stats 2>/dev/null | sed -nE 's/.*backlog ([0-9]+)b.*/\1/p' |
        head -1)"
    [ "${backlog:-0}" -gt 0 ] || break
    sleep 1
done
sleep 1
kill -TERM "$record_pid" 2>/dev/null || true
wait "$record_pid" 2>/dev/null || true
TGW_TESTBED_ID="$TESTBED_ID" scripts/testbed stats >"$WORK/tc.txt" 2>&1 || true
shaper_dropped="$(sed -nE 's/.*\(dropped ([0-9]+),.*/\1/p' "$WORK/tc.txt" | head -1)"
shaper_dropped="${shaper_dropped:-0}"

show_outputs "$WORK/record.out"

q() { sqlite3 -batch -noheader "$LOG" "$1"; }
# The recording may hold nothing at all at this rate; an absent table counts as no sample.
recorded_tables="$(sqlite3 -batch -noheader "$REC" "SELECT COUNT(*) FROM sqlite_master WHERE name = 'samples'" \
    2>/dev/null || echo 0)"
qr() {
    if [ "$recorded_tables" = 1 ]; then
        REC="$REC" LOG="$LOG" camp_query "$1"
    else
        echo "${2:-0}"
    fi
}

# Memory: the figures, the least-squares slope, and the queue rebuilt from the log.
first_arrival_ns="$(q "SELECT MIN(a) FROM (SELECT MIN(arrival_ns) AS a FROM dropped_samples
                                          UNION ALL SELECT MIN(arrival_ns) FROM forwarded_samples)")"
q "SELECT arrival_ns, logged_ns, LENGTH(payload) FROM dropped_samples
   UNION ALL SELECT arrival_ns, forwarded_ns, payload_bytes FROM forwarded_samples" | tr '|' ' ' >"$WORK/queue.txt"
python3 - "$WORK/rss.txt" "$WORK/queue.txt" "${first_arrival_ns:-0}" "$publish_end_ns" "$DURATION" \
    >"$WORK/memory.txt" <<'EOF'
import sys
rss_file, queue_file, first_arrival, end, duration = sys.argv[1:6]
first_arrival, end, duration = int(first_arrival), int(end), int(duration)
rows = [list(map(int, line.split())) for line in open(rss_file) if len(line.split()) == 6]
def at_or_before(t):
    before = [r for r in rows if r[0] <= t]
    return before[-1] if before else rows[0]
start = at_or_before(first_arrival)
minute = next((r for r in rows if r[0] >= start[0] + 60e9), rows[-1])
last = at_or_before(end)
peak = max(rows, key=lambda r: r[1])
def slope(window_s, column):
    """KiB/min of a least-squares line through the samples of the last window_s of publishing, and how many."""
    fit = [r for r in rows if end - window_s * 1e9 <= r[0] <= end]
    n = len(fit)
    if n < 2:
        return 0.0, n
    mx = sum(r[0] for r in fit) / n / 60e9
    my = sum(r[column] for r in fit) / n
    sxx = sum((r[0] / 60e9 - mx) ** 2 for r in fit)
    return sum((r[0] / 60e9 - mx) * (r[column] - my) for r in fit) / sxx, n
# The queue: +payload from arrival to when the sample was logged or forwarded (departures first on a tie).
events = []
for line in open(queue_file):
    a, b, size = map(int, line.split())
    events += [(a, 0, size), (b, -1, -size)]
events.sort()
q = q_peak = n_q = n_peak = 0
for t, kind, size in events:
    q += size
    n_q += 1 if size > 0 else -1
    q_peak, n_peak = max(q_peak, q), max(n_peak, n_q)
def row(name, r):
    print(name, r[1], r[2], r[3], r[4], r[5], "%.1f" % ((r[0] - start[0]) / 1e9))
row("start", start)
row("minute", minute)
row("peak", peak)
row("end", last)
for name, window in (("slope80", duration * 4 // 5), ("slope50", duration // 2)):
    vm, n = slope(window, 1)
    anon, _ = slope(window, 2)
    print(name, "%.1f" % vm, "%.1f" % anon, n, "%.1f" % (window / 60))
print("queue", q_peak, n_peak)
EOF
fig() { awk -v k="$1" -v c="$2" '$1 == k { print $c }' "$WORK/memory.txt"; }
rss_start="$(fig start 2)" rss_peak="$(fig peak 2)"
slope="$(fig slope50 2)" slope_min="$(fig slope50 5)"
queue_peak="$(fig queue 2)" queue_peak_samples="$(fig queue 3)"
overhead_kib=$((rss_start + MARGIN_KIB))
limit_kib=$((CAP_KIB + overhead_kib))
log_files="$(cd "$WORK" && echo robot-log.db*)"
log_du_kib="$(cd "$WORK" && du -ck robot-log.db* | awk 'END { print $1 }')"
log_rows="$(q "SELECT (SELECT COUNT(*) FROM dropped_samples) || ' dropped, ' ||
                      (SELECT COUNT(*) FROM forwarded_samples) || ' forwarded'")"
log_logical="$(q "SELECT page_count * page_size FROM pragma_page_count(), pragma_page_size()")"
echo
echo "== memory (gateway VmRSS, KiB; RssAnon / RssFile / RssShmem; s from the first sample's arrival)"
for k in start minute peak end; do
    printf '%-25s %6s KiB  (%s / %s / %s)  at %s s, on-robot log %s bytes (file and WAL)\n' \
        "$(case $k in start) echo 'at start' ;; minute) echo 'after 1 min' ;; peak) echo 'peak' ;;
           end) echo 'at the end of publishing' ;; esac)" \
        "$(fig "$k" 2)" "$(fig "$k" 3)" "$(fig "$k" 4)" "$(fig "$k" 5)" "$(fig "$k" 7)" "$(fig "$k" 6)"
done
for k in slope80 slope50; do
    echo "growth over the last $(fig "$k" 5) min of publishing ($(fig "$k" 4) samples, least squares): VmRSS" \
        "$(fig "$k" 2) KiB/min, RssAnon $(fig "$k" 3) KiB/min"
done
echo "queue cap: $CAP_MIB MiB = $CAP_KIB KiB ($cap_note); the queue's peak, rebuilt from the on-robot log:" \
    "$queue_peak bytes of payload in $queue_peak_samples samples"
echo "fixed overhead: VmRSS at start $rss_start KiB + margin $MARGIN_KIB KiB = $overhead_kib KiB;" \
    "cap + overhead = $limit_kib KiB"
echo "on-robot log on disk after the gateway stopped: $log_du_kib KiB (du: $log_files), $log_logical bytes of pages;" \
    "$log_rows rows"
check "peak VmRSS under the cap plus the fixed overhead" "a <= b" "$rss_peak" "$limit_kib"
# Tighter than the cap while the queue stays far below it: above its start, VmRSS rose by no more than the margin
# and what the queue held at its peak.
check "peak VmRSS at most start + margin + the queue's peak payload" "a <= b" "$rss_peak" \
    "$((overhead_kib + (queue_peak + 1023) / 1024))"
check "VmRSS grew at most $MAX_SLOPE_KIB_MIN KiB/min over the last $slope_min min" "a <= b" "$slope" \
    "$MAX_SLOPE_KIB_MIN"

echo
echo "== accounting per topic"
printf '%-12s %9s %8s %9s %6s %7s %7s %7s %8s %8s %6s %9s %8s %8s %6s\n' topic published gw_recv forwarded queued \
    expired doomed evicted oversize shutdown failed no_reader log_fwd recorded lost
REASONS=(expired doomed evicted oversize shutdown write_failed no_reader)
lost_total=0
for t in A B C D; do
    topic="telemetry/$t"
    published="$(awk -v t="$topic" '$2 == t { print $5 }' "$WORK/robot.out")"
    # The gateway's exit summary, by its header's names: topic received forwarded queued REASON... ttl
    declare -A gw=()
    while read -r name value; do gw[$name]="$value"; done < <(awk -v t="$topic" '
        $1 == "topic" && $2 == "received" { for (i = 2; i <= NF; i++) h[i] = $i }
        $1 == t { for (i = 2; i in h; i++) print h[i], $i }' "$WORK/gateway.out")
    dropped=0 counted="" logged=""
    for r in "${REASONS[@]}"; do
        dropped=$((dropped + ${gw[$r]:-0}))
        counted+="$r ${gw[$r]:-?}, "
        logged+="$r $(q "SELECT COUNT(*) FROM dropped_samples WHERE topic = '$topic' AND reason = '$r'"), "
    done
    other="$(q "SELECT COUNT(*) FROM dropped_samples WHERE topic = '$topic' AND reason NOT IN
        ('expired', 'doomed', 'evicted', 'oversize', 'shutdown', 'write_failed', 'no_reader')")"
    log_fwd="$(q "SELECT COUNT(*) FROM forwarded_samples WHERE topic = '$topic'")"
    recorded="$(qr "SELECT COUNT(DISTINCT source_ns) FROM live_samples WHERE topic = '$topic'")"
    stray="$(qr "SELECT COUNT(DISTINCT source_ns) FROM live_samples WHERE topic = '$topic' AND source_ns NOT IN
        (SELECT source_time_ns FROM log.forwarded_samples WHERE topic = '$topic')")"
    lost=$((${gw[forwarded]:-0} - recorded))
    lost_total=$((lost_total + lost))
    printf '%-12s %9s %8s %9s %6s %7s %7s %7s %8s %8s %6s %9s %8s %8s %6s\n' "$topic" "${published:-?}" \
        "${gw[received]:-?}" "${gw[forwarded]:-?}" "${gw[queued]:-?}" "${gw[expired]:-?}" "${gw[doomed]:-?}" \
        "${gw[evicted]:-?}" "${gw[oversize]:-?}" "${gw[shutdown]:-?}" "${gw[write_failed]:-?}" \
        "${gw[no_reader]:-?}" "$log_fwd" "$recorded" "$lost"
    # At most one sample lost before the gateway, on the robot's own loopback (the open robot-side defect that
    # outage_test.sh also allows for); from the gateway on, exact.
    check "$topic: the gateway received all tm-robot-sim wrote, but one at most" "a >= b - 1 && a <= b && a > 0" \
        "${gw[received]:-0}" "${published:--1}"
    check "$topic: received = forwarded + queued + dropped" "a == b" "${gw[received]:-0}" \
        "$((${gw[forwarded]:-0} + ${gw[queued]:-0} + dropped))"
    check "$topic: nothing still queued at the end" "a == 0" "${gw[queued]:--1}"
    [ "$counted" = "$logged" ] && [ "$other" = 0 ] && same=1 || same=0
    check "$topic: each reason's count = its rows in the on-robot log (${logged%, })" "a == 1" "$same"
    check "$topic: forwarded = the log's forwarded_samples rows" "a == b" "$log_fwd" "${gw[forwarded]:--1}"
    check "$topic: every recorded sample was forwarded by the gateway" "a == 0" "$stray"
    check "$topic: recorded <= forwarded" "a >= 0" "$lost"
    unset gw
done
echo "lost on the WAN (forwarded, never recorded): $lost_total samples; the shaper dropped $shaper_dropped packets"
check "samples lost on the WAN at most the packets the shaper dropped" "a <= b" "$lost_total" "$shaper_dropped"

a_published="$(awk '$2 == "telemetry/A" { print $5 }' "$WORK/robot.out")"
read -r a_on_time a_rec a_mean_ms <<<"$(qr "SELECT COALESCE(SUM(receive_ns - source_ns <= 1000000000), 0), COUNT(*),
        COALESCE(printf('%.1f', AVG(receive_ns - source_ns) / 1e6), '-')
    FROM (SELECT source_ns, MIN(receive_ns) AS receive_ns FROM live_samples WHERE topic = 'telemetry/A'
          GROUP BY source_ns)" "0|0|-" | tr '|' ' ')"
a_logged="$(q "SELECT group_concat(reason || ' ' || n, ', ') FROM (SELECT reason, COUNT(*) AS n
    FROM dropped_samples WHERE topic = 'telemetry/A' GROUP BY reason)")"
echo
echo "== A at the base camp: $a_on_time of ${a_published:-?} published on time (within its 1 s TTL); $a_rec" \
    "recorded$([ "$a_rec" = 0 ] || echo " (mean $a_mean_ms ms)"); logged on the robot: ${a_logged:-none}"
no_reader="$(q "SELECT COUNT(*) || CASE WHEN COUNT(*) = 0 THEN ' rows' ELSE ' rows, logged '
    || printf('%.1f', (MIN(logged_ns) - $sim_started_ns) / 1e9) || ' to '
    || printf('%.1f', (MAX(logged_ns) - $sim_started_ns) / 1e9) || ' s after tm-robot-sim started' END
    FROM dropped_samples WHERE reason = 'no_reader'")"
echo "no_reader (no base-camp reader matched the topic): $no_reader"
echo "recorded at the base camp by topic: $(qr "SELECT COALESCE(group_concat(topic || ' ' || n, ', '), 'none') FROM
    (SELECT topic, COUNT(*) AS n FROM live_samples GROUP BY topic)" none)"
check "tm-robot-sim exited 0" "a == 0" "$sim_status"
check "the gateway exited 0" "a == 0" "$gateway_status"
echo
if [ "$fail" -eq 0 ]; then
    echo "low_rate_soak: PASS"
else
    echo "low_rate_soak: FAIL"
fi
exit "$fail"
