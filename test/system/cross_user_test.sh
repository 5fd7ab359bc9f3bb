#!/usr/bin/env bash
# System test: every program as a different user, as on a robot whose nodes run as their own users and a gateway
# installed as a service user. Fast DDS 2.9 keeps a process's shared memory to its owner, so only UDP reaches across
# users. On the robot: telemetry-gateway as one user, tm-robot-sim (the paper's workload) with Fast DDS's defaults as
# another, a second publisher with the defaults as root. At the camp: tm-basecamp relay as root, tm-basecamp record
# on the camp's domain with Fast DDS's defaults as a fourth user. The gateway receives both publishers' samples,
# and every one it forwards reaches that recording. Needs root; skipped (77) otherwise.
#   cross_user_test.sh BIN_DIR
set -euo pipefail
BIN="${1:?usage: cross_user_test.sh BIN_DIR}"
cd "$(dirname "$0")/../.."
# shellcheck source=test/system/system_test_lib.sh
source test/system/system_test_lib.sh
require_netns
require_tools setpriv sqlite3

SECONDS_PUBLISHING=10
# Users with no name and no privilege: the gateway's, a robot node's, a camp tool's.
as_gateway=(setpriv --reuid=61001 --regid=61001 --clear-groups --)
as_node=(setpriv --reuid=61002 --regid=61002 --clear-groups --)
as_tool=(setpriv --reuid=61003 --regid=61003 --clear-groups --)

start_testbed 200000 cross-user
chmod 0777 "$WORK"
printf 'E robot/battery 32 1.0 2\n' >"$WORK/battery.workload"

"${tb[@]}" basecamp "$BIN/tm-basecamp" relay --domain 1 --peer "$robot_addr" --interface "$basecamp_addr" \
    --local-domain 7 --duration 60 >"$WORK/relay.out" 2>&1 &
PIDS+=($!)
"${tb[@]}" basecamp "${as_tool[@]}" "$BIN/tm-basecamp" record --domain 7 --out "$WORK/camp.db" \
    --duration 60 >"$WORK/record.out" 2>&1 &
record_pid=$!
PIDS+=("$record_pid")
"${tb[@]}" robot "${as_gateway[@]}" "$BIN/telemetry-gateway" --robot-domain 0 --wan-domain 1 \
    --wan-peer "$basecamp_addr" --wan-interface "$veth" --sensor "qdisc:$veth" --qos qos/paper_workload.xml \
    --log "$WORK/robot-log.db" --duration 60 >"$WORK/gateway.out" 2>&1 &
gateway_pid=$!
PIDS+=("$gateway_pid")
"${tb[@]}" robot "${as_node[@]}" "$BIN/tm-robot-sim" --domain 0 --workload paper --rate-hz 5 \
    --duration "$SECONDS_PUBLISHING" --linger 2 --wait-match 20 >"$WORK/node.out" 2>&1 &
node_pid=$!
PIDS+=("$node_pid")
"${tb[@]}" robot "$BIN/tm-robot-sim" --domain 0 --workload "$WORK/battery.workload" \
    --duration "$SECONDS_PUBLISHING" --linger 2 --wait-match 20 >"$WORK/root-node.out" 2>&1 &
root_node_pid=$!
PIDS+=("$root_node_pid")
wait "$node_pid" "$root_node_pid" || true
sleep 3
kill -TERM "$gateway_pid" "$record_pid" 2>/dev/null || true
wait "$gateway_pid" "$record_pid" 2>/dev/null || true
grep -H "no subscriber" "$WORK/node.out" "$WORK/root-node.out" || true

recorded() { sqlite3 -batch -noheader "file:$WORK/camp.db?mode=ro" "SELECT COUNT(*) FROM samples WHERE topic = '$1'"; }
# The gateway's summary row: topic received forwarded ...
gateway_column() { awk -v t="$1" -v c="$2" '$1 == t && NF >= 11 { print $c; exit }' "$WORK/gateway.out"; }
for topic in telemetry/A telemetry/B telemetry/C telemetry/D robot/battery; do
    echo "$topic: the gateway received $(gateway_column "$topic" 2), forwarded $(gateway_column "$topic" 3);" \
        "$(recorded "$topic") in the camp tool's recording"
done
# One at most may miss the gateway's best-effort reader on the robot's loopback (as in outage_test.sh).
for topic in telemetry/A telemetry/B telemetry/C telemetry/D; do
    check "$topic: the gateway (one user) received the samples of another user's node" "a >= b - 1" \
        "$(gateway_column "$topic" 2)" $((5 * SECONDS_PUBLISHING))
done
check "robot/battery: and those of root's node" "a >= b - 1" "$(gateway_column robot/battery 2)" \
    $((2 * SECONDS_PUBLISHING))
# A new topic's first sample may go to the on-robot log, before the camp has matched its new WAN writer.
for topic in telemetry/A telemetry/B telemetry/C telemetry/D robot/battery; do
    check "$topic: a third user's camp tool recorded every sample the gateway forwarded" "a == b && b > 0" \
        "$(recorded "$topic")" "$(gateway_column "$topic" 3)"
done
[ "$fail" -eq 0 ] || tail -n 20 "$WORK"/*.out
exit "$fail"
