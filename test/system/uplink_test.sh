#!/usr/bin/env bash
# Commands back to the robot (issue 21, part 4) on the testbed, its robot -> base camp direction shaped at
# 25,000 bit/s and saturated by the paper's workload (55,560 bit/s of payload offered). The testbed's base camp ->
# robot direction is not shaped, a channel of its own: the gateway runs with --duplex full. The camp as it should
# run: tm-basecamp relay is its one participant on the WAN, with --uplink rt/rover1/cmd_vel, and a camp program on
# the camp's own domain (tm-robot-sim, a writer's defaults: reliable) publishes commands at 10 Hz with a Lifespan
# of 200 ms on rt/rover1/cmd_vel, and stray ones on rt/rover1/not_listed; the gateway has --uplink rt/cmd_vel. On
# the robot a recorder with Fast DDS's defaults reads the robot domain. Checks: at least 99 % of the commands reach
# the robot within their TTL, nothing of the topic not listed reaches the robot domain, every command is accounted
# for by the relay and the gateway, and A still reaches the base camp 99 % on time. Mid-run the robot's radio drops
# for DOWN_S seconds (issue 44, part 5): commands reach the robot again within 1 s of the link coming back, and the
# floors above are asserted outside the outage (from DOWN_MARGIN_S before it went down until 2 s after it came back).
# Needs root; skipped (77) otherwise.
#   uplink_test.sh BIN_DIR
set -euo pipefail
BIN="${1:?usage: uplink_test.sh BIN_DIR}"
cd "$(dirname "$0")/../.."
# shellcheck source=test/system/system_test_lib.sh
source test/system/system_test_lib.sh
require_netns
require_tools sqlite3
start_testbed 25000 uplink
DURATION=30
WARMUP=8
DOWN_AT_S=12
DOWN_S=5
DOWN_MARGIN_S=0.5

printf 'cmd rt/rover1/cmd_vel 48 0.2 10\nstray rt/rover1/not_listed 48 0.2 10\n' >"$WORK/commands"
"${tb[@]}" robot "$BIN/telemetry-gateway" --robot-domain 0 --wan-domain 1 --wan-interface "$robot_addr" \
    --wan-peer "$basecamp_addr" --robot-name rover1 --uplink rt/cmd_vel --duplex full --sensor fixed:25000 \
    --qos qos/paper_workload.xml --log "$WORK/robot.db" >"$WORK/gateway.out" 2>&1 &
gateway=$!
PIDS+=("$gateway")
"${tb[@]}" basecamp "$BIN/tm-basecamp" relay --domain 1 --peer "$robot_addr" --interface "$basecamp_addr" \
    --local-domain 2 --local-interface 127.0.0.1 --uplink rt/rover1/cmd_vel --out "$WORK/camp.db" \
    >"$WORK/camp.out" 2>&1 &
camp=$!
PIDS+=("$camp")
# What the robot's programs see of the commands (and of the stray topic, which must be nothing). Those topics
# alone: a reader of the telemetry would let tm-robot-sim's --wait-match start before the gateway's readers match.
"${tb[@]}" robot "$BIN/tm-basecamp" record --domain 0 --interface 127.0.0.1 --report-period 0 \
    --topic rt/cmd_vel --topic rt/not_listed --topic rt/rover1/not_listed --out "$WORK/commands.db" \
    >"$WORK/robot-record.out" 2>&1 &
robot_record=$!
PIDS+=("$robot_record")
# Every command the camp's program writes, as the camp's domain sees it: what the robot should get.
"${tb[@]}" basecamp "$BIN/tm-basecamp" record --domain 2 --interface 127.0.0.1 --report-period 0 \
    --topic rt/rover1/cmd_vel --out "$WORK/written.db" >"$WORK/camp-record.out" 2>&1 &
camp_record=$!
PIDS+=("$camp_record")
sleep "$WARMUP"

"${tb[@]}" robot "$BIN/tm-robot-sim" --domain 0 --interface 127.0.0.1 --workload paper --rate-hz 5 \
    --duration "$DURATION" --linger 0 --wait-match 10 >"$WORK/telemetry.out" 2>&1 &
telemetry=$!
PIDS+=("$telemetry")
"${tb[@]}" basecamp "$BIN/tm-robot-sim" --domain 2 --interface 127.0.0.1 --workload "$WORK/commands" \
    --duration "$DURATION" --linger 0 --wait-match 10 >"$WORK/commands.out" 2>&1 &
commands=$!
PIDS+=("$commands")
sleep "$DOWN_AT_S"
down_ns=$(date +%s%N)
"${tb[@]}" robot ip link set "$veth" down
sleep "$DOWN_S"
"${tb[@]}" robot ip link set "$veth" up
back_ns=$(wait_link_up robot "$veth")
echo "the robot's radio down for $(((back_ns - down_ns) / 1000000)) ms from ${DOWN_AT_S} s"
wait "$telemetry" || true
wait "$commands" || true
sleep 2
for pid in "$gateway" "$robot_record" "$camp" "$camp_record"; do kill -TERM "$pid" 2>/dev/null || true; done
for pid in "$gateway" "$robot_record" "$camp" "$camp_record"; do wait "$pid" 2>/dev/null || true; done
# Outside the outage: from DOWN_MARGIN_S before the link went down until 2 s after it came back.
from_ns=$(awk -v d="$down_ns" -v m="$DOWN_MARGIN_S" 'BEGIN { printf "%.0f", d - m * 1e9 }')
until_ns=$((back_ns + 2000000000))
outside="(source_ns < $from_ns OR source_ns >= $until_ns)"

written=$(awk '$2 == "rt/rover1/cmd_vel" { print $5 }' "$WORK/commands.out")
"$BIN/tm-basecamp" report "$WORK/commands.db" --offered "rt/cmd_vel=${written:-0}" >"$WORK/commands-report.txt" 2>&1 ||
    true
# report's row: topic ttl_s offered received on_time %on_time mean_ms sd_ms max_ms, and robot for a fleet
read -r _ ttl offered received on_time _ <<<"$(awk '$1 == "rt/cmd_vel" && (NF == 9 || NF == 10) { print; exit }' \
    "$WORK/commands-report.txt")"
check "the base camp wrote commands for the whole run (${written:-none})" "a >= 0.9 * 10 * b" "${written:-0}" \
    "$DURATION"
check "rt/cmd_vel on the robot: TTL ${ttl:-?} s, from the command's Lifespan" "a == 0.2" "${ttl:-0}"
written_outside=$(sqlite3 -batch -noheader "$WORK/written.db" "SELECT COUNT(DISTINCT source_ns) FROM samples
    WHERE topic = 'rt/rover1/cmd_vel' AND $outside")
on_time_outside=$(sqlite3 -batch -noheader "$WORK/commands.db" "SELECT COUNT(*) FROM (SELECT source_ns,
    MIN(receive_ns) AS receive_ns FROM samples WHERE topic = 'rt/cmd_vel' AND $outside GROUP BY source_ns)
    WHERE receive_ns - source_ns <= 200000000")
check "rt/cmd_vel on the robot, outside the outage: ${on_time_outside:-0} of ${written_outside:-0} within their TTL" \
    "b > 200 && a >= 0.99 * b" "${on_time_outside:-0}" "${written_outside:-0}"
first_back_ms=$(sqlite3 -batch -noheader "$WORK/commands.db" "SELECT printf('%.0f', (MIN(receive_ns) - $back_ns) / 1e6)
    FROM samples WHERE topic = 'rt/cmd_vel' AND receive_ns >= $back_ns")
check "commands on the robot again within 1 s of the link coming back (${first_back_ms:-never} ms)" \
    "a != \"\" && a <= 1000" "${first_back_ms:-}"
check "rt/cmd_vel on the robot: nothing after its TTL (${received:-0} received)" "a == b" "${received:-0}" \
    "${on_time:-0}"
stray=$(awk '$1 ~ /not_listed/ { n++ } END { print n + 0 }' "$WORK/commands-report.txt" "$WORK/robot-record.out")
check "nothing of rt/rover1/not_listed on the robot domain" "a == 0" "$stray"
# Each hop's count. The relay's summary: "  uplink TOPIC: T commands taken from the camp, W onto the WAN, L written
# while no gateway listened (lost), E past their Lifespan (dropped), F failed"; the gateway's: "uplink WAN -> ROBOT:
# R received, D delivered, E expired before they came (never delivered), F failed, N written while no robot reader
# listened; ...".
relay_line=$(grep '^  uplink rt/rover1/cmd_vel: ' "$WORK/camp.out" || true)
relay_taken=$(sed -nE 's/.*: ([0-9]+) commands taken.*/\1/p' <<<"$relay_line")
relay_sent=$(sed -nE 's/.*, ([0-9]+) onto the WAN.*/\1/p' <<<"$relay_line")
relay_expired=$(sed -nE 's/.*, ([0-9]+) past their Lifespan.*/\1/p' <<<"$relay_line")
relay_unheard=$(sed -nE 's/.*, ([0-9]+) written while no gateway listened.*/\1/p' <<<"$relay_line")
gateway_line=$(grep '^uplink rt/rover1/cmd_vel -> rt/cmd_vel: ' "$WORK/gateway.out" || true)
read -r up_received up_delivered up_expired up_failed up_unheard <<<"$(sed -nE \
    's/.*: ([0-9]+) received, ([0-9]+) delivered, ([0-9]+) expired.*, ([0-9]+) failed, ([0-9]+) written.*/\1 \2 \3 \4 \5/p' \
    <<<"$gateway_line")"
check "the relay took every command from the camp's domain (${relay_taken:-none} of $written)" "a == b" \
    "${relay_taken:-0}" "${written:-0}"
# A command already past its Lifespan when the relay takes it (a loaded camp) is dropped there, as it should be.
check "the relay sent them onto the WAN (${relay_sent:-none}, ${relay_unheard:-?} before the gateway listened, \
${relay_expired:-?} past their Lifespan)" "a > 0 && a + ${relay_unheard:-0} + ${relay_expired:-0} == b" \
    "${relay_sent:-0}" "${relay_taken:-0}"
# What the relay wrote while the robot's radio was down is lost on the way (a Lifespan of 200 ms outlives no repair).
written_down=$(sqlite3 -batch -noheader "$WORK/written.db" "SELECT COUNT(DISTINCT source_ns) FROM samples
    WHERE topic = 'rt/rover1/cmd_vel' AND source_ns >= $down_ns AND source_ns < $back_ns")
check "the gateway received what the relay sent (${up_received:-none}), but for the ${written_down:-?} written while \
the radio was down" "b > 0 && a >= 0.99 * (b - ${written_down:-0})" "${up_received:-0}" "${relay_sent:-0}"
check "the gateway's commands add up: ${up_received:-?} = ${up_delivered:-?} delivered + ${up_expired:-?} expired \
+ ${up_unheard:-?} with no robot reader" "a > 0 && a == b" "${up_received:-0}" \
    "$((${up_delivered:-0} + ${up_expired:-0} + ${up_failed:-0} + ${up_unheard:-0}))"

published=$(awk '$2 == "telemetry/A" { print $5 }' "$WORK/telemetry.out")
"$BIN/tm-basecamp" report "$WORK/camp.db" --robot-log "$WORK/robot.db" --offered "rover1/telemetry/A=${published:-0}" \
    >"$WORK/camp-report.txt" 2>&1 || true
a_offered=$(sqlite3 -batch -noheader "$WORK/robot.db" "SELECT COUNT(*) FROM (SELECT source_time_ns AS source_ns
    FROM forwarded_samples WHERE topic LIKE '%telemetry/A' UNION ALL SELECT source_time_ns FROM dropped_samples
    WHERE topic LIKE '%telemetry/A') WHERE $outside")
a_on_time=$(sqlite3 -batch -noheader "$WORK/camp.db" "SELECT COUNT(*) FROM (SELECT source_ns, MIN(receive_ns) AS
    receive_ns FROM samples WHERE topic = 'rover1/telemetry/A' AND $outside GROUP BY source_ns)
    WHERE receive_ns - source_ns <= 1000000000")
check "rover1/telemetry/A at the base camp, outside the outage: ${a_on_time:-0} of ${a_offered:-0} on time" \
    "b > 80 && a >= 0.99 * b" "${a_on_time:-0}" "${a_offered:-0}"
logged=$(awk '$1 == "rover1/telemetry/D" && NF == 17 { print $6 + $7; exit }' "$WORK/camp-report.txt")
echo "the link was saturated: D samples the gateway dropped for the link: ${logged:-?}"

cat "$WORK/commands-report.txt"
if [ "$fail" -ne 0 ]; then
    for f in gateway.out commands.out telemetry.out robot-record.out camp.out camp-record.out camp-report.txt; do
        echo "--- $f"
        cat "$WORK/$f"
    done
fi
exit "$fail"
