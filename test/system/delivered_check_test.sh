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
# Not a check: the check corrects the sensor in two ways, the scheduler waiting for the shaper's backlog to drain
# and the budget's cap once a queue stands and grows. The backlog alone sometimes keeps the queue short for all of
# the 20 s (once in a CI run), and the checks above fail without --delivered-check (82 % of samples over 250 ms).
if grep -q 'delivered-rate check: the link delivers less than the sensor' "$out"; then
    echo "note: the check capped the sensor's rate"
else
    echo "note: the shaper's backlog alone held the gateway back; no cap in this run"
fi
exit "$fail"
