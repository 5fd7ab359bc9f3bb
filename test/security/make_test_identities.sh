#!/usr/bin/env bash
# The ctest fixture of the security tests: scripts/make-certs into OUT, then identities spoilt one way each, for the
# start-up checks (base::SecurityFiles::load) to refuse:
#   OUT/bad/missing_key/            gateway/ without key.pem
#   OUT/bad/wrong_ca/               gateway/ with the intruder's cert.pem and key.pem (another identity CA)
#   OUT/bad/tampered_permissions/   gateway/ with one word of permissions.p7s's signed text changed
#   OUT/bad/tampered_governance/    gateway/ with one word of governance.p7s's signed text changed
#   make_test_identities.sh MAKE_CERTS OUT
set -euo pipefail
make_certs="${1:?usage: make_test_identities.sh MAKE_CERTS OUT}"
out="${2:?usage: make_test_identities.sh MAKE_CERTS OUT}"
"$make_certs" "$out"
rm -rf "$out/bad"
for bad in missing_key wrong_ca tampered_permissions tampered_governance; do
    mkdir -p "$out/bad/$bad"
    cp "$out"/gateway/*.pem "$out"/gateway/*.p7s "$out/bad/$bad/"
done
rm "$out/bad/missing_key/key.pem"
cp "$out/intruder/cert.pem" "$out/intruder/key.pem" "$out/bad/wrong_ca/"
sed -i 's|<default>DENY</default>|<default>ALLOW</default>|' "$out/bad/tampered_permissions/permissions.p7s"
sed -i 's|<allow_unauthenticated_participants>false|<allow_unauthenticated_participants>true|' \
    "$out/bad/tampered_governance/governance.p7s"
# Each spoilt file differs from the original, or the tests would test nothing.
! cmp -s "$out/gateway/permissions.p7s" "$out/bad/tampered_permissions/permissions.p7s"
! cmp -s "$out/gateway/governance.p7s" "$out/bad/tampered_governance/governance.p7s"
echo "make_test_identities: $out/bad"
