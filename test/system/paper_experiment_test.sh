#!/usr/bin/env bash
# System test: scripts/paper-experiment --quick --reliable-wan (it asserts what it prints): the base camp's
# recorder reads the gateway reliably, as it reads the control's reliable publishers. Its results go in a
# directory of this test's own, removed afterwards whatever the outcome. Needs root; the script exits 77
# (skipped) otherwise.
#   paper_experiment_test.sh BIN_DIR
set -euo pipefail
BIN="${1:?usage: paper_experiment_test.sh BIN_DIR}"
cd "$(dirname "$0")/../.."
OUT="$(mktemp -d "${TMPDIR:-/tmp}/tgw-paper-experiment-test.XXXXXX")"
trap 'rm -rf "$OUT"' EXIT
TGW_BIN="$BIN" scripts/paper-experiment --quick --reliable-wan --out "$OUT"
