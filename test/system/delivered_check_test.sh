#!/usr/bin/env bash
# System test: a rate sensor that reads 30 % high (fixed:26000 over a 20,000 bit/s tbf) corrected by the gateway's
# delivered-rate check from the shaper's own counters: no standing queue, A on time. Needs root; skipped (77)
# otherwise.
#   delivered_check_test.sh BIN_DIR
set -euo pipefail
BIN="${1:?usage: delivered_check_test.sh BIN_DIR}"
cd "$(dirname "$0")/../.."
# shellcheck source=test/system/system_test_lib.sh
source test/system/system_test_lib.sh
require_netns

out="$(mktemp "${TMPDIR:-/tmp}/tgw-delivered-check-test.XXXXXX")"
trap 'rm -f "$out"' EXIT
TGW_BIN="$BIN" scripts/demo --no-build --rate 20000 --duration 20 --sensor fixed:26000 --delivered-check \
    --no-control | tee "$out"

# tm-basecamp report's row: topic ttl_s offered received on_time %on_time mean_ms sd_ms max_ms
a_row="$(awk '$1 == "telemetry/A" && NF == 9 { print; exit }' "$out")"
# "shaper while publishing: queue mean M B (T ms at R bit/s), max X B, over 250 ms in P % of N samples; D packets dropped"
queue="$(grep '^shaper while publishing:' "$out" || true)"
[ -n "$a_row" ] && [ -n "$queue" ] || { echo "FAIL: no report or queue line in the demo's output"; exit 1; }
read -r _ _ offered received on_time _ <<<"$a_row"
long_pct="$(sed -E 's/.*over 250 ms in ([0-9]+) %.*/\1/' <<<"$queue")"
dropped="$(sed -E 's/.*; ([0-9]+) packets dropped.*/\1/' <<<"$queue")"

check "the shaper's queue stands over 250 ms in at most 10 % of samples" "a <= 10" "$long_pct"
check "the shaper dropped at most 2 packets while the robot published" "a <= 2" "$dropped"
check "A on time for 99 % of what reached the base camp" "a >= 0.99 * b" "$on_time" "$received"
check "A reached the base camp for 90 % of what was published" "a >= 0.90 * b" "$received" "$offered"
grep -q 'delivered-rate check: the link delivers less than the sensor' "$out" ||
    { echo "FAIL: the gateway never capped the sensor's rate"; fail=1; }
exit "$fail"
