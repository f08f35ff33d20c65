#!/usr/bin/env bash
# Fails when a header under core/ names a concept of a layer above it:
# redundancy's pair vocabulary, arbitration, the supervisor, the link guard
# or the TAP bridge (issue 25 item 2; docs/ARCHITECTURE.md). Comments are
# left out: the core may say what it serves, its code may not name it.
#
#   deploy/check_core_layering.sh [CORE_DIR]     (default: core/ of this tree)
set -euo pipefail
core=${1:-"$(cd "$(dirname "$0")/.." && pwd)/core"}
[ -d "$core" ] || { echo "check_core_layering: no such directory: $core" >&2; exit 2; }

words='Arbitration|Arbiter|arbitration|LinkGuard|link_guard|linkguard|Supervisor|supervisor|TapBridge|tap_bridge'
words+='|HandOff|Handoff|hand_off|handoff|Switchover|switchover|ForceStandby|force_standby|StandbyForced'
words+='|Collision|PartnerLost|PartnerFound|PartnerMismatch|RedStateChanged|CommTimeout|NoActiveMaster'
words+='|ecpair/redundancy|redundancy::'

found=0
while IFS= read -r -d '' header; do
    # Code only: // comments and /* */ blocks removed, line numbers kept.
    hits=$(sed -e 's#//.*$##' "$header" |
           awk '{ line = $0; out = "";
                  while (line != "") {
                      if (in_block) { e = index(line, "*/"); if (e == 0) { line = ""; break } line = substr(line, e + 2); in_block = 0 }
                      s = index(line, "/*"); if (s == 0) { out = out line; break }
                      out = out substr(line, 1, s - 1); line = substr(line, s + 2); in_block = 1 }
                  print out }' |
           grep -nE "$words" || true)
    if [ -n "$hits" ]; then
        found=1
        while IFS= read -r hit; do echo "${header}:${hit}"; done <<< "$hits"
    fi
done < <(find "$core" -name '*.hpp' -print0 | sort -z)

if [ "$found" -ne 0 ]; then
    echo "check_core_layering: the headers above name concepts of the layers above core/ (move them up)" >&2
    exit 1
fi
echo "check_core_layering: no header under $core names a layer above it"
