#!/usr/bin/env bash
# Runs a program with bad input and checks what an operator sees: exit code 2 and a message that names the
# flag, file or interface at fault.
#   expect_usage_error.sh 'TEXT THE MESSAGE NAMES' PROGRAM ARGS...
set -uo pipefail
expected="${1:?usage: expect_usage_error.sh TEXT PROGRAM ARGS...}"
shift
output="$("$@" 2>&1)"
status=$?
echo "$output"
if [ "$status" -ne 2 ]; then
    echo "FAIL: exit code $status, expected 2"
    exit 1
fi
if ! grep -qF -- "$expected" <<<"$output"; then
    echo "FAIL: the message does not name '$expected'"
    exit 1
fi
echo "ok: exit 2, naming '$expected'"
