#!/usr/bin/env bash
# --config FILE.yaml as a user meets it (issue 46): every example in config/ loads, and what --print-config prints
# is a file that, given back, prints the same; every flag in --help has a key; a flag on the command line wins over
# the file. The files at fault under test/config are cli_config_* cases (test/cli/CMakeLists.txt).
#   config_files_test.sh BIN_DIR
set -uo pipefail
BIN="${1:?usage: config_files_test.sh BIN_DIR}"
cd "$(dirname "$0")/../.."
WORK="$(mktemp -d)"
trap 'rm -rf "$WORK"' EXIT
fail=0
no() { echo "FAIL: $*"; fail=1; }

# command FILE: the program whose configuration FILE is
command_of() {
    case "$(basename "$1")" in
        basecamp-*) echo "$BIN/tm-basecamp relay" ;;
        *) echo "$BIN/telemetry-gateway" ;;
    esac
}

for example in config/*.yaml; do
    # shellcheck disable=SC2046
    if ! $(command_of "$example") --config "$example" --print-config >"$WORK/printed.yaml" 2>"$WORK/err.txt"; then
        no "$example does not load: $(cat "$WORK/err.txt")"
        continue
    fi
    # shellcheck disable=SC2046
    $(command_of "$example") --config "$WORK/printed.yaml" --print-config >"$WORK/again.yaml" 2>&1 ||
        no "$example: what --print-config printed does not load: $(cat "$WORK/again.yaml")"
    if cmp -s "$WORK/printed.yaml" "$WORK/again.yaml"; then
        echo "ok: $example loads, and what it prints, given back, prints the same"
    else
        no "$example: printed twice, the two differ"
        diff "$WORK/printed.yaml" "$WORK/again.yaml"
    fi
done

# Every flag of --help has a key in --print-config (set, or commented when it has no value).
for command in "$BIN/telemetry-gateway" "$BIN/tm-basecamp relay --local-domain 2"; do
    # shellcheck disable=SC2086
    $command --help >"$WORK/help.txt" 2>&1
    # shellcheck disable=SC2086
    $command --print-config >"$WORK/keys.yaml" 2>&1 || no "$command --print-config failed: $(cat "$WORK/keys.yaml")"
    flags="$(grep -oE '^ +--[a-z][a-z0-9-]*' "$WORK/help.txt" | tr -d ' ' | sort -u)"
    missing=0
    for flag in $flags; do
        case "$flag" in --help | --help-all | --version | --config | --print-config) continue ;; esac
        key="$(echo "${flag#--}" | tr - _)"
        grep -qE "^(# )?$key:" "$WORK/keys.yaml" || { no "$command: $flag has no key '$key'"; missing=1; }
    done
    [ "$missing" = 1 ] || echo "ok: $command: each of its $(echo "$flags" | wc -w) flags has a key"
done

# The command line wins over the file.
"$BIN/telemetry-gateway" --config test/config/flags_win.yaml --robot-domain 5 --print-config >"$WORK/won.yaml"
if grep -qx 'robot_domain: 5' "$WORK/won.yaml" && grep -qx 'wan_peer: \[127.0.0.1\]' "$WORK/won.yaml"; then
    echo "ok: --robot-domain 5 on the command line wins over the file's 3, the file's wan_peer stays"
else
    no "the command line did not win: $(grep -E '^(robot_domain|wan_peer):' "$WORK/won.yaml")"
fi
exit "$fail"
