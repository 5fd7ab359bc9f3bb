#!/usr/bin/env bash
# Cross-vendor QoS test: Cyclone DDS programs on both sides of telemetry-gateway, on loopback, with the QoS of
# two rows of the QoS-matching issue's table:
#   - partitions: a publisher in partition "site7"; a reader in "site7" gets every sample, one in "site8" none;
#   - a latched topic: a transient-local keyed publisher writes once (100 samples, 50 instances) and stays; a
#     transient-local reader that joins after 3 x the TTL gets the last sample of each instance and nothing older.
#     Twice: a publisher that sends the key hash (GenerateKeyhash), and one with Cyclone's defaults, which sends
#     none, whose key hash the gateway computes from the type's IDL (--idl). The first checks the IDL: the hash
#     the gateway computes is the one Cyclone sent.
#
#   run_cross_vendor_qos.sh GATEWAY XV_PUB XV_SUB
set -euo pipefail
[ $# -eq 3 ] || { echo "usage: $0 GATEWAY XV_PUB XV_SUB" >&2; exit 2; }
GATEWAY="$1" PUB="$2" SUB="$3"
# shellcheck source=test/integration/cyclone/xv_lib.sh
source "$(dirname "$0")/xv_lib.sh"

PARTITIONED_TOPIC="xv/partitioned/$RUN"
LATCHED_TOPIC="xv/latched/$RUN"
PLAIN_LATCHED_TOPIC="xv/latchedplain/$RUN"
COUNT=24
LATCHED_COUNT=100
INSTANCES=50
TTL_S=1
TIMEOUT_S=40
# Long enough for the partition-mismatched reader to have matched had the gateway ignored partitions.
NONE_WINDOW_S=12

echo "cross-vendor QoS: robot domain $ROBOT_DOMAIN, WAN domain $WAN_DOMAIN, topics $PARTITIONED_TOPIC, $LATCHED_TOPIC"
start sub-site7 env XV_PARTITION=site7 "$SUB" "$WAN_DOMAIN" "$PARTITIONED_TOPIC" blob "$COUNT" 1 "$TIMEOUT_S"
SUB_IN=$LAST_PID
start sub-site8 env XV_PARTITION=site8 XV_EXPECT_NONE=1 "$SUB" "$WAN_DOMAIN" "$PARTITIONED_TOPIC" blob "$COUNT" 1 \
    "$NONE_WINDOW_S"
SUB_OUT=$LAST_PID
start_gateway $((TIMEOUT_S + 10)) --default-ttl "$TTL_S" --idl "$(dirname "$0")"
start pub-site7 env XV_PARTITION=site7 "$PUB" "$ROBOT_DOMAIN" "$PARTITIONED_TOPIC" blob "$COUNT" 1 "$TIMEOUT_S"
# Cyclone sends no key hash by default: GenerateKeyhash makes it send one.
start pub-latched env XV_TRANSIENT_LOCAL=1 XV_ROUNDS=1 \
    CYCLONEDDS_URI="${CYCLONEDDS_URI/<\/Domain>/<Internal><GenerateKeyhash>true<\/GenerateKeyhash><\/Internal><\/Domain>}" "$PUB" "$ROBOT_DOMAIN" "$LATCHED_TOPIC" keyed \
    "$LATCHED_COUNT" "$INSTANCES" "$TIMEOUT_S" 0
start pub-latched-plain env XV_TRANSIENT_LOCAL=1 XV_ROUNDS=1 "$PUB" "$ROBOT_DOMAIN" "$PLAIN_LATCHED_TOPIC" keyed \
    "$LATCHED_COUNT" "$INSTANCES" "$TIMEOUT_S" 0

status=0
# Each latched publisher writes its round once the gateway's reader has matched it.
for name in pub-latched pub-latched-plain; do
    for _ in $(seq 1 200); do
        grep -q "round 1 written" "$WORK/$name.out" && break
        sleep 0.1
    done
    if ! grep -q "round 1 written" "$WORK/$name.out"; then
        echo "cross-vendor QoS: $name never matched the gateway"
        status=1
    fi
done
if [ "$status" -eq 0 ]; then
    sleep $((3 * TTL_S + 1))
    start sub-late env XV_TRANSIENT_LOCAL=1 XV_FIRST=$((LATCHED_COUNT - INSTANCES)) "$SUB" "$WAN_DOMAIN" \
        "$LATCHED_TOPIC" keyed "$LATCHED_COUNT" "$INSTANCES" 20
    SUB_LATE=$LAST_PID
    start sub-late-plain env XV_TRANSIENT_LOCAL=1 XV_FIRST=$((LATCHED_COUNT - INSTANCES)) "$SUB" "$WAN_DOMAIN" \
        "$PLAIN_LATCHED_TOPIC" keyed "$LATCHED_COUNT" "$INSTANCES" 20
    SUB_LATE_PLAIN=$LAST_PID
    wait "$SUB_LATE" || status=1
    wait "$SUB_LATE_PLAIN" || status=1
fi
wait "$SUB_IN" || status=1
wait "$SUB_OUT" || status=1
# Neither warning: the computed key hash is the one Cyclone sent, and every sample of the plain publisher got one.
if grep -E "key hash computed from the type's IDL|sends no key hash" "$WORK/gateway.out"; then
    echo "cross-vendor QoS: the gateway could not compute a key hash as Cyclone does"
    status=1
fi
finish "$status" sub-site7 sub-site8 sub-late sub-late-plain pub-site7 pub-latched pub-latched-plain gateway
