#!/usr/bin/env bash
# systemd-analyze verify on deploy/systemd/ecpaird@.service, with the
# programs pointed at this build: the unit must parse without a single
# complaint (unknown keys, bad values, missing executables).
#   systemd_unit_test.sh UNIT ECPAIRD LINKGUARD
set -euo pipefail
unit=$1 ecpaird=$2 linkguard=$3
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
sed -e "s|/usr/local/bin/ecpaird|$ecpaird|g" -e "s|/usr/local/bin/ecpair-linkguard|$linkguard|g" "$unit" \
  >"$dir/ecpaird@controller-a.service"
grep -q '^Type=notify$' "$dir/ecpaird@controller-a.service"
grep -q '^WatchdogSec=' "$dir/ecpaird@controller-a.service"
grep -q '^ExecStopPost=.*--down$' "$dir/ecpaird@controller-a.service"
complaints=$(systemd-analyze verify --man=no "$dir/ecpaird@controller-a.service" 2>&1 || echo "systemd-analyze failed")
if [ -n "$complaints" ]; then
  echo "$complaints"
  exit 1
fi
echo "ecpaird@.service verifies cleanly"
