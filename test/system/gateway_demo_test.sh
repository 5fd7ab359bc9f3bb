#!/usr/bin/env bash
# System test: the paper's workload through the real gateway over a tbf-shaped veth between two network
# namespaces (scripts/demo), against the control over the same link. Needs root; skipped (77) otherwise.
#   gateway_demo_test.sh BIN_DIR
set -euo pipefail
BIN="${1:?usage: gateway_demo_test.sh BIN_DIR}"
cd "$(dirname "$0")/../.."
# shellcheck source=test/system/system_test_lib.sh
source test/system/system_test_lib.sh
require_netns

out="$(mktemp "${TMPDIR:-/tmp}/tgw-demo-test.XXXXXX")"
trap 'rm -f "$out"' EXIT
TGW_BIN="$BIN" scripts/demo --no-build --rate 20000 --duration 20 | tee "$out"

# Rows of tm-basecamp report: topic ttl_s offered received on_time %on_time mean_ms sd_ms max_ms
table() {  # $1: the scenario's heading prefix
    awk -v h="$1" 'index($0, h) == 1 { f = 1; next } f && /^telemetry\// { print } f && /^on time:/ { exit }' "$out"
}
gateway="$(table '-- with the gateway')"
control="$(table '-- control')"
[ -n "$gateway" ] && [ -n "$control" ] || { echo "FAIL: no report tables in the demo's output"; exit 1; }

field() {  # $1: table, $2: topic, $3: column
    awk -v t="$2" -v c="$3" '$1 == t { print $c }' <<<"$1"
}
a_received="$(field "$gateway" telemetry/A 4)"
a_on_time="$(field "$gateway" telemetry/A 5)"
a_offered="$(field "$gateway" telemetry/A 3)"
check "gateway: A on time for 99 % of what reached the base camp" "a >= 0.99 * b" "$a_on_time" "$a_received"
check "gateway: A reached the base camp for 90 % of what was published" "a >= 0.90 * b" "$a_received" "$a_offered"
check "gateway: A mean transmission time under 300 ms" "a < 300" "$(field "$gateway" telemetry/A 7)"
check "gateway beats the control for A" "a > b" "$a_on_time" "$(field "$control" telemetry/A 5)"
prev=101
for t in A B C D; do
    pct="$(field "$gateway" "telemetry/$t" 6)"
    check "gateway: no priority inversion at $t (${pct} % after ${prev} %)" "a <= b + 5" "$pct" "$prev"
    prev="$pct"
done
exit "$fail"
