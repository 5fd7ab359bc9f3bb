# Sourced by the system tests: skipping where network namespaces cannot be made, and one line per assertion.

# Exits 77 (ctest's skip) unless this runs as root with iproute2.
require_netns() {
    if [ "$(id -u)" -ne 0 ] || ! command -v ip >/dev/null; then
        echo "SKIP: needs root and iproute2 for network namespaces"
        exit 77
    fi
}

# check DESCRIPTION CONDITION A [B]: prints ok or FAIL; CONDITION is awk over a and b. A failure sets fail=1.
fail=0
check() {
    if awk -v a="$3" -v b="${4:-0}" "BEGIN { exit !($2) }"; then
        echo "ok: $1"
    else
        echo "FAIL: $1 (a=$3 b=${4:-})"
        fail=1
    fi
}
