#!/usr/bin/env bash
# The Debian packages as an operator meets them (issue 46): scripts/package's cpack run into a scratch directory;
# each package's files, control fields and conffiles; both unpacked into a fresh root, where the programs
# run (--version, and --print-config of the /etc files the services read); the units checked with
# systemd-analyze verify in that root (the host's own units copied beside them, as on a robot with systemd).
#   package_test.sh BUILD_DIR
set -uo pipefail
BUILD="$(cd "${1:?usage: package_test.sh BUILD_DIR}" && pwd)"
for tool in cpack dpkg-deb systemd-analyze; do
    command -v "$tool" >/dev/null || { echo "package_test: $tool is missing; skipped"; exit 77; }
done
WORK="$(mktemp -d)"
trap 'rm -rf "$WORK"' EXIT
fail=0
ok() { echo "ok: $*"; }
no() { echo "FAIL: $*"; fail=1; }

(cd "$BUILD" && cpack -G DEB -B "$WORK/packages" >"$WORK/cpack.log" 2>&1) || { cat "$WORK/cpack.log"; exit 1; }
robot="$(ls "$WORK"/packages/telemetry-gateway_*.deb 2>/dev/null)"
camp="$(ls "$WORK"/packages/telemetry-gateway-basecamp_*.deb 2>/dev/null)"
[ -f "$robot" ] && [ -f "$camp" ] || { ls "$WORK/packages"; echo "FAIL: expected the two packages"; exit 1; }
echo "built: $(basename "$robot") ($(du -k "$robot" | cut -f1) KiB), $(basename "$camp") ($(du -k "$camp" | cut -f1) KiB)"

# has PACKAGE FILE...: each FILE is in PACKAGE
has() {
    local package=$1 file
    shift
    dpkg-deb -c "$package" | awk '{ print $NF }' >"$WORK/list.txt"
    for file in "$@"; do
        grep -qx "./${file#/}" "$WORK/list.txt" && ok "$(basename "$package") has $file" ||
            no "$(basename "$package") lacks $file"
    done
}
has "$robot" /usr/bin/telemetry-gateway /usr/bin/tm-sense /usr/bin/tm-robot-sim /usr/bin/tm-sim \
    /usr/lib/systemd/system/telemetry-gateway.service /etc/telemetry-gateway/gateway.yaml \
    /usr/share/telemetry-gateway/qos/paper_workload.xml /usr/share/telemetry-gateway/config/robot-ros2.yaml \
    /usr/share/telemetry-gateway/config/basecamp-relay.yaml /usr/share/doc/telemetry-gateway/README.md \
    /usr/lib/sysctl.d/60-telemetry-gateway.conf
has "$camp" /usr/bin/tm-basecamp /usr/lib/systemd/system/tm-basecamp-relay.service /etc/telemetry-gateway/relay.yaml \
    /usr/lib/sysctl.d/60-telemetry-gateway-basecamp.conf
if dpkg-deb -c "$robot" | awk '{ print $NF }' | grep -q '^./usr/bin/tm-basecamp$'; then
    no "the robot's package carries tm-basecamp"
fi

for package in "$robot" "$camp"; do
    name="$(dpkg-deb -f "$package" Package)"
    depends="$(dpkg-deb -f "$package" Depends)"
    grep -q 'libfastrtps' <<<"$depends" && ok "$name depends on Fast DDS ($depends)" ||
        no "$name: Depends lacks Fast DDS: '$depends'"
    dpkg-deb --ctrl-tarfile "$package" | tar -x -C "$WORK" ./conffiles ./postinst 2>/dev/null
    [ -s "$WORK/conffiles" ] && grep -q '^/etc/telemetry-gateway/' "$WORK/conffiles" &&
        ok "$name: conffiles $(tr '\n' ' ' <"$WORK/conffiles")" || no "$name: no conffile under /etc/telemetry-gateway"
    [ -x "$WORK/postinst" ] && grep -q 'net.core.rmem_max' "$WORK/postinst" &&
        ok "$name: postinst raises net.core.rmem_max" || no "$name: no postinst raising net.core.rmem_max"
    rm -f "$WORK/conffiles" "$WORK/postinst"
done

# A fresh root with both packages unpacked: the programs run from it, reading the files the services read.
ROOT="$WORK/root"
mkdir -p "$ROOT"
dpkg-deb -x "$robot" "$ROOT" && dpkg-deb -x "$camp" "$ROOT"
version="$("$ROOT/usr/bin/telemetry-gateway" --version 2>&1)"
[[ "$version" == "telemetry-gateway "* ]] && ok "the unpacked telemetry-gateway runs: $version" ||
    no "the unpacked telemetry-gateway --version: $version"
"$ROOT/usr/bin/telemetry-gateway" --config "$ROOT/etc/telemetry-gateway/gateway.yaml" --print-config \
    >"$WORK/gateway.txt" 2>&1 && ok "telemetry-gateway --config /etc/telemetry-gateway/gateway.yaml loads" ||
    no "the shipped gateway.yaml does not load: $(cat "$WORK/gateway.txt")"
"$ROOT/usr/bin/tm-basecamp" relay --config "$ROOT/etc/telemetry-gateway/relay.yaml" --print-config \
    >"$WORK/relay.txt" 2>&1 && ok "tm-basecamp relay --config /etc/telemetry-gateway/relay.yaml loads" ||
    no "the shipped relay.yaml does not load: $(cat "$WORK/relay.txt")"

# The units, as systemd would load them on a machine with both packages installed.
cp -rn /usr/lib/systemd/system/. "$ROOT/usr/lib/systemd/system/" 2>/dev/null
for unit in telemetry-gateway.service tm-basecamp-relay.service; do
    if systemd-analyze verify --root="$ROOT" "$ROOT/usr/lib/systemd/system/$unit" >"$WORK/verify.txt" 2>&1 &&
        [ ! -s "$WORK/verify.txt" ]; then
        ok "systemd-analyze verify $unit: no complaint"
    else
        no "systemd-analyze verify $unit: $(cat "$WORK/verify.txt")"
    fi
done
exit "$fail"
