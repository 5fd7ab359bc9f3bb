# Sourced by the loopback tests that run the programs: a work directory ($work; TGW_KEEP_DIR=DIR keeps the files
# there), the PIDs of what the test started ($pids, each killed at exit if still running), and the cleanup.
work=${TGW_KEEP_DIR:-$(mktemp -d)}
pids=()
cleanup() {
    for pid in "${pids[@]}"; do kill "$pid" 2>/dev/null || true; done
    wait 2>/dev/null || true
    [ -n "${TGW_KEEP_DIR:-}" ] || rm -rf "$work"
}
trap cleanup EXIT
