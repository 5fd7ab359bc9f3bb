#!/usr/bin/env bash
# DDS Security against a plain participant: a Cyclone DDS publisher on the robot domain -> telemetry-gateway
# (--wan-security DIR/gateway) -> the WAN domain -> tm-basecamp relay (--security DIR/basecamp) -> a Cyclone
# subscriber on the camp's own domain, on loopback, while Cyclone DDS participants without security join the WAN
# domain. Passes when
#   - the camp's subscriber gets every sample intact (the secured path carries everything);
#   - a plain subscriber of the same topic on the WAN domain receives nothing meanwhile;
#   - what plain publishers on the WAN domain write, whether they matched anyone or not, reaches nothing: on a topic
#     of their own (first phase), and on the robot topic's name numbered past what the robot sends (second phase,
#     apart from the plain subscriber, which would take them), nothing arrives on the camp's domain, and the relay
#     relays none of it;
#   - tm-basecamp echo as DIR/basecamp prints samples of the robot topic (in compact mode: of the bundles), and
#     tm-basecamp record as DIR/intruder (another CA) records nothing at all.
#
#   run_security_plain.sh GATEWAY TM_BASECAMP XV_PUB XV_SUB CERTS_DIR [GATEWAY_FLAGS...]
set -euo pipefail
[ $# -ge 5 ] || { echo "usage: $0 GATEWAY TM_BASECAMP XV_PUB XV_SUB CERTS_DIR [GATEWAY_FLAGS...]" >&2; exit 2; }
GATEWAY="$1" BASECAMP="$2" PUB="$3" SUB="$4" CERTS="$5"
shift 5
GATEWAY_FLAGS=("$@")
# shellcheck source=test/integration/cyclone/xv_lib.sh
source "$(dirname "$0")/xv_lib.sh"

LOCAL_DOMAIN=$((WAN_DOMAIN + 1))
TOPIC="xv/secured/blob/$RUN"
INJECTED="xv/secured/injected/$RUN"
COUNT=24
# How long each phase's plain participants listen and write: past the time the secured path takes to deliver.
PHASE_S=15
TIMEOUT_S=60

echo "security vs plain: robot domain $ROBOT_DOMAIN, WAN domain $WAN_DOMAIN, local domain $LOCAL_DOMAIN"
start sub-camp "$SUB" "$LOCAL_DOMAIN" "$TOPIC" blob "$COUNT" 1 "$TIMEOUT_S"
SUB_CAMP=$LAST_PID
XV_EXPECT_NONE=1 start sub-camp-injected "$SUB" "$LOCAL_DOMAIN" "$INJECTED" blob "$COUNT" 1 "$PHASE_S"
SUB_CAMP_INJECTED=$LAST_PID
# The relay first: it is participant 0 of the WAN domain on this host, where the gateway announces itself.
start relay "$BASECAMP" relay --domain "$WAN_DOMAIN" --peer 127.0.0.1 --interface 127.0.0.1 \
    --local-domain "$LOCAL_DOMAIN" --local-interface 127.0.0.1 --duration $((TIMEOUT_S + 10)) \
    --security "$CERTS/basecamp"
sleep 1
# More announcement ports than the default 4: the Cyclone participants take some of this host's first ones.
start_gateway $((TIMEOUT_S + 10)) --wan-security "$CERTS/gateway" --wan-peer-participants 12 "${GATEWAY_FLAGS[@]}"
# In compact mode the WAN carries the robot's samples in bundles, which only the relay unpacks.
ECHO_TOPIC="$TOPIC"
[[ " ${GATEWAY_FLAGS[*]} " == *" compact "* ]] && ECHO_TOPIC="tgw/compact/bundles"
start echo-basecamp "$BASECAMP" echo "$ECHO_TOPIC" --domain "$WAN_DOMAIN" --peer 127.0.0.1 --interface 127.0.0.1 \
    --count 3 --timeout "$TIMEOUT_S" --security "$CERTS/basecamp"
ECHO_BASECAMP=$LAST_PID
start record-intruder "$BASECAMP" record --domain "$WAN_DOMAIN" --peer 127.0.0.1 --interface 127.0.0.1 \
    --out "$WORK/intruder.db" --duration "$PHASE_S" --security "$CERTS/intruder"
RECORD_INTRUDER=$LAST_PID
XV_EXPECT_NONE=1 start sub-plain "$SUB" "$WAN_DOMAIN" "$TOPIC" blob "$COUNT" 1 "$PHASE_S"
SUB_PLAIN=$LAST_PID
XV_WRITE_UNMATCHED=1 start pub-plain-injected "$PUB" "$WAN_DOMAIN" "$INJECTED" blob "$COUNT" 1 "$PHASE_S"
PUB_PLAIN_INJECTED=$LAST_PID
start pub "$PUB" "$ROBOT_DOMAIN" "$TOPIC" blob "$COUNT" 1 "$TIMEOUT_S"

status=0
wait "$SUB_CAMP" || { echo "FAIL: the camp's subscriber did not get every sample intact"; status=1; }
wait "$SUB_PLAIN" || { echo "FAIL: the plain subscriber on the WAN domain received samples"; status=1; }
wait "$SUB_CAMP_INJECTED" || { echo "FAIL: a plain publisher's own topic reached the camp's domain"; status=1; }
wait "$PUB_PLAIN_INJECTED" || true
wait "$ECHO_BASECAMP" || { echo "FAIL: tm-basecamp echo --security DIR/basecamp did not print 3 samples"; status=1; }
wait "$RECORD_INTRUDER" || { echo "FAIL: tm-basecamp record --security DIR/intruder did not run"; status=1; }
if grep -q "$TOPIC" "$WORK/record-intruder.out" || ! grep -q "rows written: 0," "$WORK/record-intruder.out"; then
    echo "FAIL: tm-basecamp record --security DIR/intruder recorded something"
    status=1
fi

# Second phase: a plain publisher on the robot topic's name, numbering up to twice what the robot sends, while a
# subscriber on the camp's domain fails on any sample numbered past the robot's.
XV_WATCH=1 start sub-camp-late "$SUB" "$LOCAL_DOMAIN" "$TOPIC" blob "$COUNT" 1 "$PHASE_S"
SUB_CAMP_LATE=$LAST_PID
XV_WRITE_UNMATCHED=1 start pub-plain-robot-name "$PUB" "$WAN_DOMAIN" "$TOPIC" blob $((COUNT * 2)) 1 "$PHASE_S"
PUB_PLAIN_ROBOT_NAME=$LAST_PID
wait "$SUB_CAMP_LATE" || { echo "FAIL: a plain publisher on the robot topic's name reached the camp's domain"; status=1; }
wait "$PUB_PLAIN_ROBOT_NAME" || true
stop_all
if grep -q "$INJECTED" "$WORK/relay.out"; then
    echo "FAIL: the relay relayed the plain publisher's topic"
    status=1
fi
# Everything the relay took on the robot topic came from the gateway: it relayed what the gateway forwarded, no more.
relayed="$(sed -n "s|^  $TOPIC: \([0-9]*\) samples relayed|\1|p" "$WORK/relay.out")"
forwarded="$(awk -v t="$TOPIC" '$1 == t { print $3 }' "$WORK/gateway.out")"
if [ -z "$relayed" ] || [ -z "$forwarded" ] || [ "$relayed" -gt "$forwarded" ]; then
    echo "FAIL: the relay relayed ${relayed:-?} samples of $TOPIC, the gateway forwarded ${forwarded:-?}"
    status=1
fi
for injector in pub-plain-injected pub-plain-robot-name; do
    if ! grep -qE "wrote [1-9][0-9]* samples" "$WORK/$injector.out"; then
        echo "FAIL: $injector wrote nothing: the test injected nothing"
        status=1
    fi
done
finish "$status" sub-camp sub-plain sub-camp-injected sub-camp-late echo-basecamp record-intruder relay \
    pub-plain-injected pub-plain-robot-name pub gateway
