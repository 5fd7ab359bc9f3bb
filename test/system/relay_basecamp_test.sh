#!/usr/bin/env bash
# System test: the base camp as a team runs it (scripts/demo --relay): tm-basecamp relay is the camp's one
# participant on the WAN domain and republishes into the camp's own domain, where tm-basecamp record, with Fast
# DDS's defaults, records. Over a 20,000 bit/s tbf: A on time as without the relay, no standing queue, and the
# relay passed on every sample of A. Needs root; skipped (77) otherwise.
#   relay_basecamp_test.sh BIN_DIR
set -euo pipefail
BIN="${1:?usage: relay_basecamp_test.sh BIN_DIR}"
cd "$(dirname "$0")/../.."
# shellcheck source=test/system/system_test_lib.sh
source test/system/system_test_lib.sh
require_netns

KEEP="$(mktemp -d "${TMPDIR:-/tmp}/tgw-relay-test.XXXXXX")"
DEMO_OUTPUTS+=("$KEEP")
trap 'rm -rf "${DEMO_OUTPUTS[@]}"' EXIT
run_demo relay-basecamp --rate 20000 --duration 20 --relay --no-control --keep "$KEEP"
read_demo_result "$out" telemetry/A
check "the shaper's queue stands over 250 ms in at most 10 % of samples" "a <= 10" "$long_pct"
check "A on time at the camp's domain for 99 % of what was published" "a >= 0.99 * b" "$on_time" "$offered"
relayed="$(sed -n 's/^  telemetry\/A: \([0-9]*\) samples relayed$/\1/p' "$KEEP/gateway.relay.out")"
check "the relay passed on every sample of A that reached the camp" "a >= b" "${relayed:-0}" "$on_time"
exit "$fail"
