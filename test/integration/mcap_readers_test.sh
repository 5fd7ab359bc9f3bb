#!/usr/bin/env bash
# MCAP files tm-basecamp writes, read by other projects' readers (test/readers/check_mcap.mjs: @mcap/core, the
# Foxglove omgidl parser and deserializer). A gateway on loopback bridges tm-robot-sim's paper workload and a
# publisher of a type known only from its TypeObject (announced_types_publisher); tm-basecamp record writes SQLite
# and an lz4 MCAP at once; export writes the SQLite recording as zstd and as uncompressed MCAP. Each file must hold
# every recorded sample, bytes and times equal, with schemas for the project's types and the announced one. The
# gateway plans for 30,000 bit/s, less than the workload, and logs what it cannot send: the mission archive of its
# log and the recording (merge), exported too, has the samples that stayed on the robot on channels of their own.
# Last, one sample of each project type with known members (project_type_samples), exported, must decode to them.
set -euo pipefail
BIN=$1
READERS=$2
ROBOT=$((200 + ($$ + 7) % 15 * 2))  # 200..228; the test runs alone (RUN_SERIAL)
WAN=$((ROBOT + 1))
source "$(dirname "$0")/loopback_test_lib.sh"

"$BIN/telemetry-gateway" --robot-domain "$ROBOT" --wan-domain "$WAN" --wan-peer 127.0.0.1 --sensor fixed:30000 \
    --log "$work/robot.db" --duration 14 >"$work/gateway.out" 2>&1 &
gateway=$!
pids+=($!)
"$BIN/tm-basecamp" record --domain "$WAN" --peer 127.0.0.1 --out "$work/recording.db" --mcap "$work/live.mcap" \
    --compression lz4 --duration 11 >"$work/record.out" 2>&1 &
record=$!
pids+=("$record")
sleep 1
"$BIN/announced_types_publisher" "$ROBOT" FlatReading robot/reading >/dev/null 2>&1 &
publisher=$!
pids+=("$publisher")
"$BIN/tm-robot-sim" --domain "$ROBOT" --duration 6 >"$work/sim.out" 2>&1
kill "$publisher"
wait "$record"
cat "$work/record.out"
wait "$gateway"
"$BIN/tm-basecamp" merge "$work/robot.db" "$work/recording.db" --out "$work/mission.db"
"$BIN/tm-basecamp" export "$work/mission.db" --mcap "$work/mission.mcap"
sqlite3 -separator $'\t' "$work/mission.db" \
    "SELECT CASE WHEN fate = 'received' OR backfilled THEN topic WHEN fate = 'dropped'
                 THEN 'dropped/' || reason || '/' || topic ELSE 'lost/' || topic END,
            type_name, log_ns, source_ns, hex(payload)
     FROM (SELECT *, COALESCE(CASE WHEN backfilled THEN source_ns END, receive_ns, logged_ns, forwarded_ns,
                              source_ns) AS log_ns FROM mission_samples)
     ORDER BY log_ns, id" >"$work/mission.tsv"
dropped=$(sqlite3 "$work/mission.db" "SELECT COUNT(*) FROM mission_samples WHERE fate = 'dropped'")
echo "mission archive: $(wc -l <"$work/mission.tsv") samples, $dropped dropped on the robot"

# Small chunks: many of them, each found through its index.
"$BIN/tm-basecamp" export "$work/recording.db" --mcap "$work/export.mcap" --chunk-size 4096
"$BIN/tm-basecamp" export "$work/recording.db" --mcap "$work/plain.mcap" --compression none
sqlite3 -separator $'\t' "$work/recording.db" \
    "SELECT topic, type_name, log_ns, source_ns, hex(payload)
     FROM (SELECT *, CASE WHEN backfilled THEN source_ns ELSE receive_ns END AS log_ns FROM samples)
     ORDER BY log_ns, id" >"$work/samples.tsv"
# record --mcap writes what came live; backfill goes to the recording, and export takes it from there.
sqlite3 -separator $'\t' "$work/recording.db" \
    "SELECT topic, type_name, receive_ns, source_ns, hex(payload) FROM samples WHERE NOT backfilled
     ORDER BY receive_ns, id" >"$work/live.tsv"
echo "recorded: $(wc -l <"$work/samples.tsv") samples, $(wc -l <"$work/live.tsv") of them live"

schemas=(tgw::idl::PaperMessage tgw::idl::GatewayStatus tgw_test::FlatReading)
fail=0
for file in "live.mcap lz4 live.tsv" "export.mcap zstd samples.tsv" "plain.mcap none samples.tsv"; do
    set -- $file
    compression=$([ "$2" = none ] && echo "" || echo "$2")
    echo "== $1"
    node "$READERS/check_mcap.mjs" "$work/$1" "$work/$3" "$compression" --sensor fixed:30000 "${schemas[@]}" || fail=1
done
echo "== mission.mcap"
if [ "$dropped" -eq 0 ]; then
    echo "FAIL: nothing was dropped on the robot at 30,000 bit/s: the archive's channels of dropped samples go untested"
    fail=1
fi
node "$READERS/check_mcap.mjs" "$work/mission.mcap" "$work/mission.tsv" zstd --sensor fixed:30000 tgw::idl::PaperMessage || fail=1

# Every project type, one sample each with known members, decoded member by member from its schema alone.
echo "== types.mcap"
"$BIN/project_type_samples" "$work/types.db" "$work/types.json"
"$BIN/tm-basecamp" export "$work/types.db" --mcap "$work/types.mcap"
sqlite3 -separator $'\t' "$work/types.db" \
    "SELECT topic, type_name, receive_ns, source_ns, hex(payload) FROM samples ORDER BY receive_ns, id" >"$work/types.tsv"
node "$READERS/check_mcap.mjs" "$work/types.mcap" "$work/types.tsv" zstd --expect "$work/types.json" \
    tgw::idl::PaperMessage std_msgs::msg::dds_::String_ tgw::idl::KeyedReading tgw::idl::ReceiverReport \
    tgw::idl::RobotPose tgw::idl::GatewayStatus || fail=1
exit "$fail"
