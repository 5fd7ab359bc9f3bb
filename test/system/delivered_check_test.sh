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

run_demo delivered-check-test --rate 20000 --duration 20 --sensor fixed:26000 --delivered-check --no-control
read_demo_result "$out" telemetry/A

check "the shaper's queue stands over 250 ms in at most 10 % of samples" "a <= 10" "$long_pct"
check "the shaper dropped at most 2 packets while the robot published" "a <= 2" "$dropped"
check "A on time for 99 % of what reached the base camp" "a >= 0.99 * b" "$on_time" "$received"
check "A reached the base camp for 90 % of what was published" "a >= 0.90 * b" "$received" "$offered"
grep -q 'delivered-rate check: the link delivers less than the sensor' "$out" ||
    { echo "FAIL: the gateway never capped the sensor's rate"; fail=1; }
exit "$fail"
