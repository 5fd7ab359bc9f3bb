#!/usr/bin/env bash
# System test: the paper's workload through the gateway to a base camp whose recorder reads reliably, as ROS 2
# readers do (scripts/demo --reliable-wan: reliable WAN writers, their heartbeats charged to the budget as they
# leave). Over a 20,000 bit/s tbf: A on time, no standing queue. Over 40,000 bit/s: A, B and C on time.
# Needs root; skipped (77) otherwise.
#   reliable_basecamp_test.sh BIN_DIR
set -euo pipefail
BIN="${1:?usage: reliable_basecamp_test.sh BIN_DIR}"
cd "$(dirname "$0")/../.."
# shellcheck source=test/system/system_test_lib.sh
source test/system/system_test_lib.sh
require_netns

run_demo reliable-basecamp-20k --rate 20000 --duration 20 --reliable-wan --no-control
read_demo_result "$out" telemetry/A
check "20,000 bit/s: the shaper's queue stands over 250 ms in at most 10 % of samples" "a <= 10" "$long_pct"
check "20,000 bit/s: the shaper dropped at most 2 packets while the robot published" "a <= 2" "$dropped"
check "20,000 bit/s: A on time for 99 % of what was published" "a >= 0.99 * b" "$on_time" "$offered"
grep -q '(profile)' "$out" || { echo "FAIL: the gateway did not take the TTLs from the reliable profiles"; fail=1; }

run_demo reliable-basecamp-40k --rate 40000 --duration 20 --reliable-wan --no-control
read_demo_result "$out" telemetry/A
check "40,000 bit/s: the shaper's queue stands over 250 ms in at most 10 % of samples" "a <= 10" "$long_pct"
for topic in telemetry/A telemetry/B telemetry/C; do
    read_demo_result "$out" "$topic"
    check "40,000 bit/s: $topic on time for 99 % of what was published" "a >= 0.99 * b" "$on_time" "$offered"
done
exit "$fail"
