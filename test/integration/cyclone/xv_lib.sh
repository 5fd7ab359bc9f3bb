# Sourced by the cross-vendor tests: domain ids of this run, Cyclone on loopback, and the programs started,
# stopped at exit whatever the outcome.

# Domain ids of this run: port 7400 + 250 * id must stay below 65536, so ids up to 232.
ROBOT_DOMAIN=$((120 + (RANDOM + $$) % 50))
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
