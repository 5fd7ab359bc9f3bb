#!/usr/bin/env bash
# System test: scripts/paper-experiment --quick (it asserts what it prints), its results in a directory of this
# test's own, removed afterwards whatever the outcome. Needs root; the script exits 77 (skipped) otherwise.
#   paper_experiment_test.sh BIN_DIR
set -euo pipefail
BIN="${1:?usage: paper_experiment_test.sh BIN_DIR}"
cd "$(dirname "$0")/../.."
OUT="$(mktemp -d "${TMPDIR:-/tmp}/tgw-paper-experiment-test.XXXXXX")"
trap 'rm -rf "$OUT"' EXIT
TGW_BIN="$BIN" scripts/paper-experiment --quick --out "$OUT"
