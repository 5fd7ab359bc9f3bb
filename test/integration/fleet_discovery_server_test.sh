#!/usr/bin/env bash
# Two robots, one base camp, discovery through a Fast DDS Discovery Server (issue 21, parts 1 and 2), as programs
# on loopback: Debian's fast-discovery-server (fastdds-tools), two telemetry-gateways as its clients (rover1 in
# standard WAN mode, rover2 in compact mode), each bridging tm-robot-sim's paper workload from its own robot
# domain, and the base camp's relay, a super client, recording what it takes off the WAN. Nobody names a peer.
# Commands go back to rover1 (--uplink rt/cmd_vel; relay --uplink rt/rover1/cmd_vel), published on the camp's domain.
# Checks: every topic of each robot arrives under the robot's name, the relay recorded exactly what each gateway
# says it forwarded, and every command the relay sent once rover1's gateway listened reached that gateway.
set -euo pipefail
BIN=$1
QOS=$2
source "$(dirname "$0")/loopback_test_lib.sh"
ROBOT1=$((140 + $$ % 15 * 4))  # 140..199 in fours: apart from the in-process tests' domains and parallel runs
ROBOT2=$((ROBOT1 + 1))
WAN=$((ROBOT1 + 2))
CAMP=$((ROBOT1 + 3))
PORT=$((21000 + $$ % 4000))  # the server's UDP port
SERVER=127.0.0.1:$PORT

server_program=$(command -v fast-discovery-server || true)
if [ -z "$server_program" ]; then
    echo "FAIL: fast-discovery-server not found: scripts/install-deps installs Debian's fastdds-tools"
    exit 1
fi
"$server_program" -i 0 -l 127.0.0.1 -p "$PORT" >"$work/server.out" 2>&1 &
pids+=("$!")
"$BIN/tm-basecamp" relay --domain "$WAN" --discovery-server "$SERVER" --local-domain "$CAMP" \
    --uplink rt/rover1/cmd_vel --out "$work/camp.db" --duration 40 >"$work/relay.out" 2>&1 &
relay=$!
pids+=("$relay")
"$BIN/telemetry-gateway" --robot-domain "$ROBOT1" --wan-domain "$WAN" --wan-discovery-server "$SERVER" \
    --robot-name rover1 --uplink rt/cmd_vel --sensor fixed:1000000 --qos "$QOS" --no-log --duration 30 \
    >"$work/rover1.out" 2>&1 &
gateway1=$!
pids+=("$gateway1")
"$BIN/telemetry-gateway" --robot-domain "$ROBOT2" --wan-domain "$WAN" --wan-discovery-server "$SERVER" \
    --robot-name rover2 --wan-mode compact --sensor fixed:1000000 --qos "$QOS" --no-log --duration 30 \
    >"$work/rover2.out" 2>&1 &
gateway2=$!
pids+=("$gateway2")
"$BIN/tm-robot-sim" --domain "$ROBOT1" --workload paper --duration 10 --wait-match 10 >"$work/sim1.out" 2>&1 &
sim1=$!
pids+=("$sim1")
"$BIN/tm-robot-sim" --domain "$ROBOT2" --workload paper --duration 10 --wait-match 10 >"$work/sim2.out" 2>&1 &
sim2=$!
pids+=("$sim2")
# Commands once both uplinks are there: --wait-match sees the relay's reader on the camp's domain, not the
# gateway's on the WAN, which appears only after the gateway has heard of the relay's writer through the server
# (what is written before, a volatile writer gives to no one).
printf 'cmd rt/rover1/cmd_vel 48 1 10\n' >"$work/commands"
sleep 4
"$BIN/tm-robot-sim" --domain "$CAMP" --workload "$work/commands" --duration 6 --wait-match 10 \
    >"$work/commands.out" 2>&1 &
commands=$!
pids+=("$commands")
wait "$sim1" "$sim2" "$commands" "$gateway1" "$gateway2"
kill -INT "$relay" 2>/dev/null || true
wait "$relay" || true

fail=0
for robot in rover1 rover2; do
    for type in A B C D; do
        # The gateway's exit summary: topic received forwarded ...; the relay's: "  NAME: N samples".
        forwarded=$(awk -v t="telemetry/$type" '$1 == t { print $3 }' "$work/$robot.out")
        recorded=$(awk -v t="$robot/telemetry/$type:" '$1 == t { print $2 }' "$work/relay.out")
        if [ -n "$forwarded" ] && [ "$forwarded" -gt 0 ] && [ "${recorded:-0}" = "$forwarded" ]; then
            echo "ok: $robot/telemetry/$type: $recorded recorded of $forwarded forwarded"
        else
            echo "FAIL: $robot/telemetry/$type: ${recorded:-none} recorded of ${forwarded:-none} forwarded"
            fail=1
        fi
    done
done
# tm-robot-sim's row: type topic data_bytes ttl_s written ...; the relay's summary: "  uplink rt/rover1/cmd_vel: T
# commands taken from the camp, W onto the WAN, L written while no gateway listened (lost), ..."; rover1's: "uplink
# rt/rover1/cmd_vel -> rt/cmd_vel: R received, ...". The first commands may go before rover1's gateway has heard of
# the relay's writer through the server (a volatile writer gives them to no one): the relay counts those apart.
written=$(awk '$2 == "rt/rover1/cmd_vel" { print $5 }' "$work/commands.out")
read -r taken sent unheard <<<"$(sed -nE \
    's/^  uplink rt\/rover1\/cmd_vel: ([0-9]+) commands taken from the camp, ([0-9]+) onto the WAN, ([0-9]+) written.*/\1 \2 \3/p' \
    "$work/relay.out")"
received=$(sed -nE 's/^uplink rt\/rover1\/cmd_vel -> rt\/cmd_vel: ([0-9]+) received.*/\1/p' "$work/rover1.out")
if [ -n "$written" ] && [ "${taken:-0}" = "$written" ] && [ "$((${sent:-0} + ${unheard:-0}))" = "$written" ] &&
    [ "$((2 * ${sent:-0}))" -ge "$written" ] && [ "${received:-0}" = "${sent:-none}" ]; then
    echo "ok: rt/rover1/cmd_vel: $received of $written commands reached rover1's gateway ($unheard written before" \
        "it listened)"
else
    echo "FAIL: rt/rover1/cmd_vel: ${written:-none} written at the camp, ${taken:-none} taken by the relay," \
        "${sent:-none} sent to a listening gateway (at least half must be), ${unheard:-none} before;" \
        "${received:-none} received by rover1's gateway"
    fail=1
fi
if [ "$fail" -ne 0 ]; then
    for f in server rover1 rover2 relay sim1 sim2 commands; do
        echo "--- $f.out"
        cat "$work/$f.out"
    done
fi
exit "$fail"
