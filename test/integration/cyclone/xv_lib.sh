# Sourced by the cross-vendor tests: domain ids of this run, Cyclone on loopback, and the programs started,
# stopped at exit whatever the outcome.

# Domain ids of this run: port 7400 + 250 * id must stay below 65536, so ids up to 232. Each run holds a slot of
# its own (a lock on a file, kept by this shell and the programs it starts): two runs that drew the same domains at
# random met, and one's gateway bridged the other's robot topic onto the WAN in plain (a secured run's plain
# subscriber then took a sample; CI, 2026-11-26).
XV_SLOTS=50
mkdir -p /tmp/tgw-xv-domains
xv_first_slot=$(((RANDOM + $$) % XV_SLOTS))
for ((xv_n = 0; xv_n < XV_SLOTS; xv_n++)); do
    XV_SLOT=$(((xv_first_slot + xv_n) % XV_SLOTS))
    exec {XV_LOCK_FD}>"/tmp/tgw-xv-domains/$XV_SLOT.lock"
    flock -n "$XV_LOCK_FD" && break
    exec {XV_LOCK_FD}>&-
done
ROBOT_DOMAIN=$((120 + XV_SLOT))
WAN_DOMAIN=$((ROBOT_DOMAIN + 55))
RUN="$$_$RANDOM"
WORK="$(mktemp -d "${TMPDIR:-/tmp}/tgw-xv.XXXXXX")"

# Cyclone on loopback only: no multicast (lo has none), discovery by unicast to the well-known participant
# ports on 127.0.0.1, where the gateway's robot and WAN participants listen.
export CYCLONEDDS_URI="<CycloneDDS><Domain Id=\"any\"><General><Interfaces><NetworkInterface address=\"127.0.0.1\"/></Interfaces><AllowMulticast>false</AllowMulticast></General><Discovery><ParticipantIndex>auto</ParticipantIndex><MaxAutoParticipantIndex>20</MaxAutoParticipantIndex><Peers><Peer Address=\"127.0.0.1\"/></Peers></Discovery></Domain></CycloneDDS>"

PIDS=()
stop_all() {
    local pid
    for pid in "${PIDS[@]}"; do kill -TERM "$pid" 2>/dev/null || true; done
    for pid in "${PIDS[@]}"; do wait "$pid" 2>/dev/null || true; done
    PIDS=()
}
trap stop_all EXIT

# start NAME COMMAND...: runs COMMAND in the background, its output in $WORK/NAME.out; sets LAST_PID.
start() {
    local name="$1"
    shift
    "$@" >"$WORK/$name.out" 2>&1 &
    LAST_PID=$!
    PIDS+=("$LAST_PID")
}

# start_gateway SECONDS [FLAGS...]: the gateway between the two domains on loopback, for xv/* topics only.
start_gateway() {
    local seconds="$1"
    shift
    start gateway "$GATEWAY" --robot-domain "$ROBOT_DOMAIN" --wan-domain "$WAN_DOMAIN" --wan-peer 127.0.0.1 \
        --wan-interface 127.0.0.1 --sensor fixed:50000000 --allow "xv/*" --log "$WORK/robot-log.db" \
        --duration "$seconds" "$@"
}

# finish STATUS NAMES...: stops everything, prints the named outputs, keeps $WORK only on failure; exits STATUS.
finish() {
    local status="$1" name
    shift
    stop_all
    for name in "$@"; do
        echo "--- $name"
        cat "$WORK/$name.out" 2>/dev/null || echo "(not started)"
    done
    if [ "$status" -eq 0 ]; then
        rm -rf "$WORK"
        echo "cross-vendor: PASSED"
    else
        echo "cross-vendor: FAILED (files in $WORK)"
    fi
    exit "$status"
}
