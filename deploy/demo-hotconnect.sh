#!/usr/bin/env bash
# README's second demo: Hot-Connect in a redundant pair. A generated segment
# (3 junctions and slaves in a line, two Hot-Connect groups of 4 slaves at
# junction ports D, groups identified by their station alias) runs in
# ecsim; the pair m1 ACTIVE / m2 INACTIVE runs it in OP. Then:
#   1. group 2 is powered off at the start: the pair reaches OP without it
#   2. group 2 is powered on: m1 finds it, identifies it and brings it to OP
#   3. group 1 is powered off: the rest stays in OP, the WKCs follow
#   4. m2 (INACTIVE) shows the same groups; a switchover hands over, m2 goes on
#   5. group 1 comes back at the new ACTIVE
#   6. an unknown slave is plugged in behind group 1: a mismatch; block-node
#      cuts it off
# and, all along, the counters show no lost frame and no WKC error.
# Run as root. ECPAIR_DEMO_NO_BUILD=1 skips the build; ECPAIR_BUILD_DIR
# points at another build tree.
set -euo pipefail
cd "$(dirname "$0")/.."
repo=$(pwd)
source deploy/lib/demo_steps.sh
source deploy/lib/topology.sh
source deploy/lib/pair_member.sh

bin=${ECPAIR_BUILD_DIR:-$repo/build}
prefix=echc$$
work=$(mktemp -d /tmp/ecpair-hc-demo.XXXXXX)

cleanup() {
  for pid in ${events_m1:-} ${events_m2:-}; do kill "$pid" 2>/dev/null || true; done
  for pid in ${m1:-} ${m2:-} ${sim:-}; do kill "$pid" 2>/dev/null && wait "$pid" 2>/dev/null || true; done
  topology_down "$prefix"
  rm -rf "$work"
}
trap cleanup EXIT

demo_build ecsim ecpaird ecpairctl ecsim-make-eni
ecsim=$bin/sim/segment/ecsim
ecpaird=$bin/supervisor/ecpaird/ecpaird
ecpairctl=$bin/supervisor/ecpairctl/ecpairctl
make_eni=$bin/sim/generator/ecsim-make-eni
ctl() { "$ecpairctl" "$1" --socket "$work/$2.sock" "${@:3}"; }
sim() { "$ecsim" ctl --control "$work/ecsim.sock" "$@" | sed 's/^/   ecsim: /'; }
groups() { ctl groups "$1" | grep -E "^Hot-Connect|^group" | sed 's/^/   /'; }
counters() { ctl status "$1" | grep -E "frames sent" | sed 's/^/   /'; }
present() { ctl status "$1" >/dev/null && "$ecpairctl" groups --socket "$work/$1.sock" | grep -q "$2"; }
done_events() { grep -c 'topology-change-done' "$work/events-$1.log" 2>/dev/null || true; }
wait_done() {  # member count-before
  for _ in $(seq 100); do [ "$(done_events "$1")" -gt "$2" ] && break; sleep 0.1; done
  grep 'topology-change-done' "$work/events-$1.log" | tail -1 | sed 's/^/   /'
}

eni=$work/hotconnect.xml
"$make_eni" --slaves 3 --groups 2 --group-slaves 4 --input-bytes 8 --output-bytes 6 --identification alias -o "$eni"

step "1. ecsim: 3 junctions/slaves in a line and two 4-slave Hot-Connect groups; group 2 is off"
topology_up "$prefix" pair
ip netns exec "$prefix-sim" "$ecsim" --eni "$eni" --main-if sim-main --red-if sim-red \
  --control "$work/ecsim.sock" --realtime-priority 70 >"$work/ecsim.log" 2>&1 &
sim=$!
wait_for 10 test -S "$work/ecsim.sock"
sim group-off 2
member() {  # name initial-state
  pair_member_config "$1" "$2" "$eni" "$work" "demo { kind: WALKING_BIT }" \
    "hot_connect { mode: AUTOMATIC detection_timeout_ms: 5000 }" >"$work/$1.textproto"
  ip netns exec "$prefix-$1" "$ecpaird" --config "$work/$1.textproto" >"$work/$1.log" 2>&1 &
}
member m1 ACTIVE; m1=$!
member m2 INACTIVE; m2=$!
wait_for 10 test -S "$work/m1.sock"
wait_for 10 test -S "$work/m2.sock"
ctl events m1 >"$work/events-m1.log" 2>&1 & events_m1=$!
ctl events m2 >"$work/events-m2.log" 2>&1 & events_m2=$!
wait_for 30 bash -c "'$ecpairctl' status --socket '$work/m1.sock' | grep -q 'master OP'" || true
wait_for 10 bash -c "'$ecpairctl' status --socket '$work/m2.sock' | grep -q 'partner seen, mirrored'" || true
groups m1
counters m1

step "2. Group 2 is powered on while the pair runs in OP"
before=$(done_events m1)
sim group-on 2
wait_done m1 "$before"
wait_for 5 present m1 "group 2 'Group 2': present" || true
groups m1
grep -E 'detect-add-groups|topology-change-detected' "$work/events-m1.log" | tail -2 | sed 's/^/   /'

step "3. Group 1 is powered off: the rest stays in OP"
before=$(done_events m1)
sim group-off 1
wait_done m1 "$before"
groups m1
counters m1
note "cyclic WKC errors so far: $(grep -c 'cyclic-wkc-error' "$work/events-m1.log" || true)"

step "4. m2 (INACTIVE) answers like m1; then ecpairctl switchover (no cycle lost)"
groups m2
ctl accept m2 2>&1 | sed 's/^/   /' || true
ctl switchover m1 | sed 's/^/   /'
wait_for 10 bash -c "'$ecpairctl' status --socket '$work/m2.sock' | grep -q 'redundancy: ACTIVE'" || true
sleep 1
groups m2

step "5. Group 1 comes back: the new ACTIVE brings it to OP"
before=$(done_events m2)
sim group-on 1
wait_done m2 "$before"
wait_for 5 present m2 "group 1 'Group 1': present" || true
groups m2
groups m1

step "6. An unknown slave plugged in behind the last slave of group 1, where nothing may join"
before=$(done_events m2)
sim plug-unknown 5 B
wait_done m2 "$before"
ctl groups m2 | sed -n '/mismatch/,$p' | sed 's/^/   /'
before=$(done_events m2)
ctl block-node m2 | sed 's/^/   /'
wait_done m2 "$before"
counters m2
note "AL transitions out of OP in ecsim's slaves that stayed: $(grep -E 'Sim (junction|IO)' "$work/ecsim.log" | grep -c 'AL OP -> ' || true)"

step "Events of m2"
grep -E 'topology|groups|mismatch|presence|takeover|port-loop' "$work/events-m2.log" | tail -20 | sed 's/^/   /'
