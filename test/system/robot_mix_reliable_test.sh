#!/usr/bin/env bash
# System test: a real robot's mix (scripts/robot-mix-experiment: six topics from 40 B to 6 kB, a keyed one, rates of
# 0.5 to 5 Hz, Lifespan = TTL, from an independent Cyclone DDS publisher) through the gateway with its defaults, read
# at the base camp by reliable readers as ROS 2 makes them: Cyclone's and Fast DDS's. The link: 80,000 bit/s for 20 s,
# then 40,000 for 12 s, whose first 2 s (what the shaper still holds from 80,000) are not asserted. With reliable
# readers, repairs and heartbeats go in the schedule: the urgent topics keep their deadlines as with best-effort
# readers. Cyclone knows the robot by its address alone (its documented unicast set-up), so it announces itself to
# ten discovery ports there: the gateway holds those it does not use, else the robot's ICMP port unreachables cost
# hazards now and then (docs/reliability.md, "A robot's mix"). Needs root; skipped (77) otherwise.
#   robot_mix_reliable_test.sh BIN_DIR
set -euo pipefail
BIN="${1:?usage: robot_mix_reliable_test.sh BIN_DIR}"
cd "$(dirname "$0")/../.."
# shellcheck source=test/system/system_test_lib.sh
source test/system/system_test_lib.sh
require_netns

OUT="$(mktemp -d "${TMPDIR:-/tmp}/tgw-robot-mix.XXXXXX")"
trap 'rm -rf "$OUT"' EXIT
TGW_BIN="$BIN" scripts/robot-mix-experiment --readers cyclone,fastdds --phases 80000:20,40000:2,40000:10 --out "$OUT"

# on_time READER TOPIC PHASE: "published on_time" of TOPIC in PHASE (1 to 3) as the experiment counted them.
on_time() {
    awk -v t="$2" -v p="$3" '$1 == t && $2 == p { print $4, $5 }' "$OUT/$1/on-time.txt"
}
for reader in cyclone fastdds; do
    for topic in mix/hazard mix/pose mix/joints mix/battery; do
        read -r published received <<<"$(on_time "$reader" "$topic" 1)"
        check "$reader: $topic >= 99 % on time at 80,000 bit/s ($received of $published)" \
            "a >= 0.99 * b && b > 0" "${received:-0}" "${published:-0}"
    done
    for topic in mix/image mix/science; do
        read -r published received <<<"$(on_time "$reader" "$topic" 1)"
        check "$reader: $topic >= 90 % on time at 80,000 bit/s ($received of $published)" \
            "a >= 0.9 * b && b > 0" "${received:-0}" "${published:-0}"
    done
    for topic in mix/hazard mix/pose; do
        read -r published received <<<"$(on_time "$reader" "$topic" 3)"
        check "$reader: $topic >= 99 % on time at 40,000 bit/s ($received of $published)" \
            "a >= 0.99 * b && b > 0" "${received:-0}" "${published:-0}"
    done
    held="$(grep -c "^telemetry-gateway: WAN discovery ports .* held" "$OUT/$reader/gateway.out" || true)"
    check "$reader: the gateway holds the WAN domain's unused discovery ports" "a == 1" "$held" 1
    grep -h "^repairs for reliable readers" "$OUT/$reader/gateway.out" || true
done
exit "$fail"
