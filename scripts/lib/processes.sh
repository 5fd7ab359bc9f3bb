# Processes a script starts and stops, by PID: only what it started is ever stopped. Sourced by the experiment
# scripts; they call stop_started on exit.

STARTED_PIDS=()

# Starts "$@" in the background with its output in $1 and remembers the PID in LAST_PID. The PID is the program
# itself (scripts/testbed exec and ip netns exec both exec).
start() {
    local out="$1"
    shift
    "$@" >"$out" 2>&1 &
    LAST_PID=$!
    STARTED_PIDS+=("$LAST_PID")
}

# Stops one started process (SIGTERM, then SIGKILL after $2 seconds, default 10) and forgets it.
stop_pid() {
    local pid="$1" grace="${2:-10}" i keep=()
    if kill -0 "$pid" 2>/dev/null; then
        kill -TERM "$pid" 2>/dev/null || true
        for ((i = 0; i < grace * 10; i++)); do
            kill -0 "$pid" 2>/dev/null || break
            sleep 0.1
        done
        kill -0 "$pid" 2>/dev/null && kill -KILL "$pid" 2>/dev/null || true
    fi
    wait "$pid" 2>/dev/null || true
    for i in "${STARTED_PIDS[@]}"; do [ "$i" = "$pid" ] || keep+=("$i"); done
    STARTED_PIDS=("${keep[@]}")
}

# Waits for one started process; returns its status.
wait_pid() {
    local pid="$1" status=0 i keep=()
    wait "$pid" || status=$?
    for i in "${STARTED_PIDS[@]}"; do [ "$i" = "$pid" ] || keep+=("$i"); done
    STARTED_PIDS=("${keep[@]}")
    return "$status"
}

# Stops everything still running that was started here.
stop_started() {
    local pid
    for pid in "${STARTED_PIDS[@]}"; do kill -TERM "$pid" 2>/dev/null || true; done
    for pid in "${STARTED_PIDS[@]}"; do wait "$pid" 2>/dev/null || true; done
    STARTED_PIDS=()
}

# "--offered topic=N" for tm-basecamp report, from tm-robot-sim's table (type topic data_bytes ttl_s written ...).
offered_args() {
    awk '$1 ~ /^[A-Z]$/ && $2 ~ /\// { printf "--offered %s=%s ", $2, $5 }' "$1"
}
