#!/usr/bin/env bash
# tm-basecamp relay --foxglove-port, with @foxglove/ws-protocol's client as Foxglove connects (test/readers/
# check_foxglove.mjs). A gateway on loopback bridges tm-robot-sim's paper workload, its status, and a type known
# only from its publisher's TypeObject; the relay serves them and records what it takes off the WAN (--out). Every
# topic must be advertised with a schema the client decodes each message with, every message must be bytes the
# relay recorded for its topic, and a client that subscribes to nothing must get nothing.
set -euo pipefail
BIN=$1
READERS=$2
ROBOT=$((200 + ($$ + 3) % 15 * 2))  # 200..228
WAN=$((ROBOT + 1))
LOCAL=$((ROBOT + 2))
source "$(dirname "$0")/loopback_test_lib.sh"

"$BIN/telemetry-gateway" --robot-domain "$ROBOT" --wan-domain "$WAN" --wan-peer 127.0.0.1 --wan-interface 127.0.0.1 \
    --sensor fixed:1000000 --duration 16 >"$work/gateway.out" 2>&1 &
pids+=($!)
"$BIN/tm-basecamp" relay --domain "$WAN" --peer 127.0.0.1 --interface 127.0.0.1 --local-domain "$LOCAL" \
    --local-interface 127.0.0.1 --out "$work/relay.db" --foxglove-port 0 --duration 13 >"$work/relay.out" 2>&1 &
relay=$!
pids+=("$relay")
"$BIN/announced_types_publisher" "$ROBOT" FlatReading robot/reading >/dev/null 2>&1 &
pids+=($!)
"$BIN/tm-robot-sim" --domain "$ROBOT" --duration 10 >"$work/sim.out" 2>&1 &
pids+=($!)
for _ in $(seq 50); do
    port=$(sed -n 's|.*Foxglove on ws://0.0.0.0:\([0-9]*\).*|\1|p' "$work/relay.out")
    [ -n "$port" ] && break
    sleep 0.1
done
[ -n "$port" ] || { cat "$work/relay.out"; echo "FAIL: the relay never said its Foxglove port"; exit 1; }
sleep 2
fail=0
node "$READERS/check_foxglove.mjs" "ws://127.0.0.1:$port" 6 fixed:1000000 "$work/received.tsv" \
    telemetry/A telemetry/B telemetry/C telemetry/D tgw/status robot/reading || fail=1
wait "$relay"
cat "$work/relay.out"

# Every message the client got is a sample the relay recorded on that topic, bytes equal.
sqlite3 -separator $'\t' "$work/relay.db" "SELECT topic, hex(payload) FROM samples WHERE NOT backfilled" | sort -u >"$work/recorded.tsv"
cut -f1,3 "$work/received.tsv" | sort -u >"$work/received_payloads.tsv"
unknown=$(comm -23 "$work/received_payloads.tsv" "$work/recorded.tsv" | wc -l)
echo "received $(wc -l <"$work/received.tsv") messages, $(wc -l <"$work/received_payloads.tsv") distinct;" \
    "$unknown not among the $(wc -l <"$work/recorded.tsv") the relay recorded"
[ "$unknown" -eq 0 ] || fail=1
sent=$(sed -n 's/.*Foxglove: \([0-9]*\) messages sent.*/\1/p' "$work/relay.out")
echo "the relay sent ${sent:-?} messages, the subscribing client received $(wc -l <"$work/received.tsv")"
[ "${sent:-0}" -ge "$(wc -l <"$work/received.tsv")" ] || fail=1
exit "$fail"
