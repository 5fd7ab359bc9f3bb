# Sourced by the system tests: skipping where network namespaces cannot be made, and one line per assertion.

# Exits 77 (ctest's skip) unless this runs as root with iproute2.
require_netns() {
    if [ "$(id -u)" -ne 0 ] || ! command -v ip >/dev/null; then
        echo "SKIP: needs root and iproute2 for network namespaces"
        exit 77
    fi
}

# Exits 77 unless every TOOL given is installed.
require_tools() {
    local tool
    for tool in "$@"; do
        command -v "$tool" >/dev/null || { echo "SKIP: needs $tool"; exit 77; }
    done
}

# check DESCRIPTION CONDITION A [B [C]]: prints ok or FAIL; CONDITION is awk over a, b and c. A failure sets fail=1.
fail=0
check() {
    if awk -v a="$3" -v b="${4:-0}" -v c="${5:-0}" "BEGIN { exit !($2) }"; then
        echo "ok: $1"
    else
        echo "FAIL: $1 (a=$3 b=${4:-}${5:+ c=$5})"
        fail=1
    fi
}

# read_demo_result FILE TOPIC: from scripts/demo's output, sets offered, received and on_time (tm-basecamp
# report's row of TOPIC) and long_pct and dropped (the "shaper while publishing" line). Exits 1 without them.
read_demo_result() {
    local row queue
    # tm-basecamp report's row: topic ttl_s offered received on_time %on_time mean_ms sd_ms max_ms, and robot for a fleet
    row="$(awk -v t="$2" '$1 == t && (NF == 9 || NF == 10) { print; exit }' "$1")"
    # "shaper while publishing: queue mean M B (T ms at R bit/s), max X B, over 250 ms in P % of N samples; D packets dropped"
    queue="$(grep '^shaper while publishing:' "$1" || true)"
    [ -n "$row" ] && [ -n "$queue" ] || { echo "FAIL: no report or queue line in the demo's output"; exit 1; }
    read -r _ _ offered received on_time _ <<<"$row"
    long_pct="$(sed -E 's/.*over 250 ms in ([0-9]+) %.*/\1/' <<<"$queue")"
    dropped="$(sed -E 's/.*; ([0-9]+) packets dropped.*/\1/' <<<"$queue")"
}

# run_demo NAME DEMO_ARGS...: runs scripts/demo with the programs of $BIN into a temporary file (removed at exit,
# with those of earlier calls and whatever else the caller put in DEMO_OUTPUTS), shown as it goes; sets out to
# the file.
DEMO_OUTPUTS=()
run_demo() {
    out="$(mktemp "${TMPDIR:-/tmp}/tgw-$1.XXXXXX")"
    shift
    DEMO_OUTPUTS+=("$out")
    trap 'rm -rf "${DEMO_OUTPUTS[@]}"' EXIT
    TGW_BIN="$BIN" scripts/demo --no-build "$@" | tee "$out"
}

# start_testbed RATE NAME [UP_ARGS...]: a testbed of its own shaped at RATE bit/s (UP_ARGS go to `scripts/testbed
# up`: --routed, --robots N) and a work directory, both removed at exit (KEEP_WORK=1 keeps the directory, to look
# into a run) with every process whose PID is added to PIDS. Sets WORK, TESTBED_ID, robot_addr, basecamp_addr, veth, tb (the
# prefix that runs a command in a namespace: "${tb[@]}" robot CMD) and robot_cyclone (a CYCLONEDDS_URI for a
# Cyclone program on the robot's loopback, where the gateway's robot participant listens).
PIDS=()
start_testbed() {
    WORK="$(mktemp -d "${TMPDIR:-/tmp}/tgw-$2.XXXXXX")"
    TESTBED_ID="$(od -An -N3 -tx1 /dev/urandom | tr -d ' \n')"
    trap stop_testbed EXIT
    TGW_TESTBED_ID="$TESTBED_ID" scripts/testbed up "$1" "${@:3}" >/dev/null
    robot_addr="$(TGW_TESTBED_ID="$TESTBED_ID" scripts/testbed info robot-addr)"
    basecamp_addr="$(TGW_TESTBED_ID="$TESTBED_ID" scripts/testbed info basecamp-addr)"
    veth="$(TGW_TESTBED_ID="$TESTBED_ID" scripts/testbed info robot-veth)"
    tb=(env TGW_TESTBED_ID="$TESTBED_ID" scripts/testbed exec)
    robot_cyclone="<CycloneDDS><Domain Id=\"any\"><General><Interfaces><NetworkInterface address=\"127.0.0.1\"/></Interfaces><AllowMulticast>false</AllowMulticast></General><Discovery><ParticipantIndex>auto</ParticipantIndex><Peers><Peer Address=\"127.0.0.1\"/></Peers></Discovery></Domain></CycloneDDS>"
}

stop_testbed() {
    local pid
    for pid in "${PIDS[@]}"; do kill -TERM "$pid" 2>/dev/null || true; done
    for pid in "${PIDS[@]}"; do wait "$pid" 2>/dev/null || true; done
    TGW_TESTBED_ID="$TESTBED_ID" scripts/testbed down 2>/dev/null || true
    if [ -n "${KEEP_WORK:-}" ]; then
        echo "outputs kept in $WORK (KEEP_WORK)" >&2
    else
        rm -rf "$WORK"
    fi
}

# wait_link_up NAMESPACE VETH: after `ip link set VETH up`, waits until the kernel reports it up (operstate, which
# IFF_RUNNING follows) and prints that moment in ns; says on stderr how long it took. The kernel's link watch runs at
# most once a second across every namespace: with other tests' links changing, up to 1 s after the command (seen in
# CI: 1,022 ms). No program can send on the link before, so a radio is back from that moment.
wait_link_up() {
    local set_ns tries=0
    set_ns=$(date +%s%N)
    until [ "$("${tb[@]}" "$1" cat "/sys/class/net/$2/operstate")" = up ]; do
        tries=$((tries + 1))
        [ "$tries" -lt 500 ] || { echo "FAIL: $2 not up 5 s after ip link set up" >&2; exit 1; }
        sleep 0.01
    done
    local up_ns
    up_ns=$(date +%s%N)
    echo "the kernel reported $2 up $(((up_ns - set_ns) / 1000000)) ms after ip link set up" >&2
    echo "$up_ns"
}

# start_paper_publisher SECONDS: tm-robot-sim publishing the paper's workload at 5 Hz on the robot's loopback (domain
# 0) for SECONDS, once the gateway's readers match, into $WORK/robot.out; sets sim_pid.
start_paper_publisher() {
    "${tb[@]}" robot "$BIN/tm-robot-sim" --domain 0 --interface 127.0.0.1 --workload paper --rate-hz 5 \
        --duration "$1" --linger 0 --wait-match 10 >"$WORK/robot.out" 2>&1 &
    sim_pid=$!
    PIDS+=("$sim_pid")
}

# start_paper_gateway SECONDS [FLAG...]: telemetry-gateway on the robot, as the paper's experiments run it (the
# TTLs of qos/paper_workload.xml, the qdisc sensor on the robot's veth, the camp's participant 0 as its peer: by
# address, or as WAN_PEER names it), with FLAGs added, for at most SECONDS, into $WORK/gateway.out with its log in
# $WORK/robot-log.db; sets gateway_pid.
start_paper_gateway() {
    "${tb[@]}" robot "$BIN/telemetry-gateway" --robot-domain 0 --wan-domain 1 --wan-peer "${WAN_PEER:-$basecamp_addr}" \
        --wan-interface "$veth" --sensor "qdisc:$veth" --qos qos/paper_workload.xml --wan-peer-participants 1 \
        --log "$WORK/robot-log.db" --duration "$1" "${@:2}" >"$WORK/gateway.out" 2>&1 &
    gateway_pid=$!
    PIDS+=("$gateway_pid")
}

# start_recording_relay SECONDS: tm-basecamp relay at the camp, as the robot's peer, recording into
# $WORK/basecamp.db (backfill too) for at most SECONDS, the camp's domain 7 on loopback, into $WORK/record.out;
# sets record_pid.
start_recording_relay() {
    "${tb[@]}" basecamp "$BIN/tm-basecamp" relay --domain 1 --peer "$robot_addr" --interface "$basecamp_addr" \
        --local-domain 7 --local-interface 127.0.0.1 --out "$WORK/basecamp.db" --duration "$1" \
        >"$WORK/record.out" 2>&1 &
    record_pid=$!
    PIDS+=("$record_pid")
}

# finish_run SIM_PID GATEWAY_PID RECORD_PID: waits for tm-robot-sim (sets sim_status); lets the gateway drain for
# 2 s, then stops it (sets gateway_status; it logs what is still queued as 'shutdown'); gives the recorder 2 s for
# what is in flight (the shaper's queue is at most 1 s deep), then stops it; the shaper's counters go to
# $WORK/tc.txt.
finish_run() {
    sim_status=0
    wait "$1" || sim_status=$?
    sleep 2
    kill -TERM "$2" 2>/dev/null || true
    gateway_status=0
    wait "$2" || gateway_status=$?
    sleep 2
    kill -TERM "$3" 2>/dev/null || true
    wait "$3" 2>/dev/null || true
    TGW_TESTBED_ID="$TESTBED_ID" scripts/testbed stats >"$WORK/tc.txt" 2>&1 || true
}

# camp_query SQL: runs SQL on the camp's recording $REC with the on-robot log $LOG attached as "log".
# live_samples: the recording's samples that came live; backfilled ones (rows of the on-robot log that missed their
# TTL, sent later in spare capacity: the gateway's default) are in samples too.
camp_query() {
    sqlite3 -batch -noheader "$REC" "ATTACH '$LOG' AS log;
        CREATE TEMP VIEW live_samples AS SELECT * FROM main.samples WHERE NOT backfilled; $1"
}

# move_address SIDE DEV OLD NEW OTHER_DEV: on a flat radio network, SIDE's (robot or basecamp) DEV loses OLD (a /30)
# and gets NEW (a /24), the link staying up (a new DHCP lease, a mesh radio's); the other side routes NEW through its
# OTHER_DEV first. Sets change_ns to the moment the old address went.
move_address() {
    local other=basecamp
    [ "$1" = robot ] || other=robot
    "${tb[@]}" "$other" ip route add "$4/32" dev "$5"
    change_ns=$(date +%s%N)
    "${tb[@]}" "$1" ip addr del "$3/30" dev "$2"
    "${tb[@]}" "$1" ip addr add "$4/24" dev "$2"
    echo "the $1's address $3 -> $4"
}

# stamp_line FILE TEXT OUT: in the background (its PID in PIDS), writes to OUT the moment (ns) TEXT first appears
# in FILE, a program's output as it runs: when the program said it did something, for a test to place it in time.
stamp_line() {
    (
        until grep -qF -- "$2" "$1" 2>/dev/null; do sleep 0.02; done
        date +%s%N >"$3"
    ) &
    PIDS+=($!)
}

# unacknowledged_rows LOG: the data rows of the on-robot log LOG the camp has not acknowledged (backfill's backlog);
# "?" while the file cannot be read.
unacknowledged_rows() {
    sqlite3 -batch -noheader "file:$1?mode=ro" "SELECT COUNT(*) FROM dropped_samples WHERE acked_ns IS NULL AND
        kind = 'data'" 2>/dev/null || echo "?"
}

# wait_acknowledged LOG SECONDS: waits until LOG has no row the camp has not acknowledged, SECONDS at most; sets
# waited to the seconds it took.
wait_acknowledged() {
    waited=0
    while [ "$(unacknowledged_rows "$1")" != 0 ] && [ "$waited" -lt "$2" ]; do
        sleep 1
        waited=$((waited + 1))
    done
}

# archive_fates ARCHIVE TOPIC_PATTERN: "PRODUCED LIVE BACKFILLED ONLY_ON_THE_ROBOT LOST" for the topics LIKE
# TOPIC_PATTERN in the mission archive ARCHIVE (tm-basecamp merge).
archive_fates() {
    sqlite3 -batch -separator ' ' "$1" "SELECT COUNT(*), COALESCE(SUM(fate = 'received'), 0),
        COALESCE(SUM(backfilled), 0), COALESCE(SUM(fate = 'dropped' AND NOT backfilled), 0),
        COALESCE(SUM(fate = 'lost'), 0) FROM mission_samples WHERE topic LIKE '$2'"
}

# a_on_time_between FROM_NS TO_NS [TOPIC]: "ON_TIME PUBLISHED" for A (TOPIC: telemetry/A, or a robot's
# rover1/telemetry/A; TTL 1 s) published in [FROM_NS, TO_NS): published as the on-robot log has them (forwarded or
# dropped), on time as the camp's recording has them.
a_on_time_between() {
    local published on_time topic="${3:-telemetry/A}"
    published="$(camp_query "SELECT COUNT(*) FROM (SELECT source_time_ns FROM log.forwarded_samples
        WHERE topic = '$topic' UNION ALL SELECT source_time_ns FROM log.dropped_samples
        WHERE topic = '$topic') WHERE source_time_ns >= $1 AND source_time_ns < $2")"
    on_time="$(camp_query "SELECT COUNT(*) FROM (SELECT source_ns, MIN(receive_ns) AS receive_ns FROM live_samples
        WHERE topic = '$topic' AND source_ns >= $1 AND source_ns < $2 GROUP BY source_ns)
        WHERE receive_ns - source_ns <= 1000000000")"
    echo "$on_time $published"
}

# finish_fleet RELAY_PID GATEWAY_PID...: once the publishers are done, lets the gateways drain for 2 s and stops
# them, gives the base camp's relay 2 s for what is in flight and stops it; the shaper's counters go to $WORK/tc.txt.
finish_fleet() {
    local relay=$1 pid
    shift
    sleep 2
    for pid in "$@"; do kill -TERM "$pid" 2>/dev/null || true; done
    for pid in "$@"; do wait "$pid" || true; done
    sleep 2
    kill -TERM "$relay" 2>/dev/null || true
    wait "$relay" 2>/dev/null || true
    TGW_TESTBED_ID="$TESTBED_ID" scripts/testbed stats >"$WORK/tc.txt" 2>&1 || true
}

# show_outputs RECORD_OUT: what the programs printed (tm-robot-sim; the gateway, with $gateway_status; the last
# lines of the recorder's RECORD_OUT) and the shaper's counters ($WORK/tc.txt).
show_outputs() {
    echo "--- tm-robot-sim"
    cat "$WORK/robot.out"
    echo "--- gateway (exit status $gateway_status)"
    cat "$WORK/gateway.out"
    echo "--- recorder"
    tail -n 5 "$1"
    echo "--- shaper"
    cat "$WORK/tc.txt"
}
