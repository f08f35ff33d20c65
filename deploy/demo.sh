#!/usr/bin/env bash
# README's main command: a redundant ecpair pair on a simulated EtherCAT
# segment, all on this machine (network namespaces, veth cables). Installs
# and builds what it needs, then shows:
#   1. ecsim: the slave chain of a real ENI (TwinCAT, 5 slaves)
#   2. ecpairctl scan: the bus as an operator sees it, compared with the ENI
#   3. the pair: m1 ACTIVE drives the slaves to OP, m2 INACTIVE forwards every
#      frame and mirrors m1's image; `ecpairctl compare` checks both images agree;
#      the masters ping each other over the TAP bridge (IP in EtherCAT frames)
#   4. a cable breaks between two slaves: the ring survives, m2 keeps mirroring
#   5. a planned switchover by API: m2 takes over hot, the slaves stay in OP
#   6. a failover: m2's controller dies (killed, its cables dark) and m1
#      takes over from its mirror
# Run as root. ECPAIR_DEMO_ENI picks another ENI; ECPAIR_DEMO_NO_BUILD=1 skips
# the build and ECPAIR_BUILD_DIR points at another build tree.
set -euo pipefail
cd "$(dirname "$0")/.."
repo=$(pwd)
source deploy/lib/topology.sh
source deploy/lib/pair_member.sh
source deploy/lib/tap_bridge.sh

eni=${ECPAIR_DEMO_ENI:-$repo/tests/data/eni/twincat_kpierczy_5slaves.xml}
bin=${ECPAIR_BUILD_DIR:-$repo/build}
prefix=ecpd$$
work=$(mktemp -d /tmp/ecpair-demo.XXXXXX)

step() { printf '\n\033[1m== %s\033[0m\n' "$*"; }
note() { printf '   %s\n' "$*"; }

cleanup() {
  for pid in ${events_m1:-} ${events_m2:-}; do kill "$pid" 2>/dev/null || true; done
  for pid in ${m1:-} ${m2:-} ${sim:-}; do kill "$pid" 2>/dev/null && wait "$pid" 2>/dev/null || true; done
  topology_down "$prefix"
  rm -rf "$work"
}
trap cleanup EXIT

wait_for() {  # seconds command...: retries the command until it succeeds
  local seconds=$1; shift
  for _ in $(seq $((seconds * 10))); do "$@" >/dev/null 2>&1 && return 0; sleep 0.1; done
  "$@"
}

if [ "${ECPAIR_DEMO_NO_BUILD:-0}" != 1 ]; then
  step "Installing dependencies and building (build/, log in build.log)"
  bash deploy/build.sh >"$repo/build.log" 2>&1 || { tail -30 "$repo/build.log"; exit 1; }
fi
ecsim=$bin/sim/segment/ecsim
ecpaird=$bin/supervisor/ecpaird/ecpaird
ecpairctl=$bin/supervisor/ecpairctl/ecpairctl
ctl() { "$ecpairctl" "$1" --socket "$work/$2.sock" "${@:3}"; }
sim() { "$ecsim" ctl --control "$work/ecsim.sock" "$@"; }
status() { ctl status "$1" | sed -n "1,${2:-7}p" | sed 's/^/   /'; }
in_state() { ctl status "$1" | grep -q "$2"; }

step "1. ecsim: the slaves of $(basename "$eni") in namespace $prefix-sim"
topology_up "$prefix" pair
ip netns exec "$prefix-sim" "$ecsim" --eni "$eni" --main-if sim-main --red-if sim-red \
  --control "$work/ecsim.sock" --pcap "$work/segment.pcap" --realtime-priority 70 >"$work/ecsim.log" 2>&1 &
sim=$!
wait_for 10 test -S "$work/ecsim.sock"
note "cables: m1-main -> slave 1 ... slave 5 -> m2-red, and m1-red <-> m2-main (master-master)"

step "2. ecpairctl scan from controller m1 (namespace $prefix-m1), before any master runs"
note "(m2's cable to the last slave is unplugged for the scan, so the last slave closes its port and frames come back)"
ip -n "$prefix-m2" link set m2-red down
wait_for 10 bash -c "'$ecsim' ctl --control '$work/ecsim.sock' status | grep -q 'red=down'"
ip netns exec "$prefix-m1" "$ecpairctl" scan --if m1-main --eni "$eni" | sed 's/^/   /'
ip -n "$prefix-m2" link set m2-red up
wait_for_carrier "$prefix-sim" sim-red
wait_for_carrier "$prefix-m2" m2-red

step "3. The pair: m1 starts ACTIVE, m2 INACTIVE (same ENI, cable redundancy, LRW split)"
member() {  # name initial-state
  pair_member_config "$1" "$2" "$eni" "$work" "demo { kind: LOOPBACK_CHECK step_cycles: 50 }" \
    "$(tap_bridge_config "$1")" >"$work/$1.textproto"
  ip netns exec "$prefix-$1" "$ecpaird" --config "$work/$1.textproto" >"$work/$1.log" 2>&1 &
}
member m1 ACTIVE; m1=$!
member m2 INACTIVE; m2=$!
wait_for 10 test -S "$work/m1.sock"
wait_for 10 test -S "$work/m2.sock"
ctl events m1 >"$work/events-m1.log" 2>&1 & events_m1=$!
ctl events m2 >"$work/events-m2.log" 2>&1 & events_m2=$!
wait_for 30 in_state m1 "master OP" || true
wait_for 10 in_state m2 "partner seen, mirrored" || true
sleep 2
status m1 8
status m2 13
note "(master PD: m1 sends its cycle counter, m2 echoes it back)"
ctl compare m1 --socket "$work/m2.sock" | sed 's/^/   /'
tap_bridge_demo "$prefix" "$work" "$ecpairctl"

step "4. A cable breaks between slave 2 and slave 3 while in OP"
sim break 2 | sed 's/^/   /'
sleep 2
status m1 4
status m2 5 | tail -2
ctl compare m1 --socket "$work/m2.sock" | sed 's/^/   /'
sim repair 2 | sed 's/^/   /'
sleep 1

step "5. Planned switchover by API: m1 steps down, m2 takes over"
ctl red-state m1 INACTIVE | sed 's/^/   /'
ctl red-state m2 ACTIVE | sed 's/^/   /'
wait_for 10 in_state m1 "partner seen, mirrored" || true
sleep 2
status m2 8
status m1 6 | tail -2
ctl compare m2 --socket "$work/m1.sock" | sed 's/^/   /'
note "AL transitions out of OP logged by ecsim: $(grep -c 'AL OP -> ' "$work/ecsim.log" || true) (0: the slaves never left OP)"

step "6. Failover: m2's controller dies (killed, its adapters dark); m1 takes over from its mirror"
kill -9 "$m2"; wait "$m2" 2>/dev/null || true; m2=
ip -n "$prefix-m2" link set m2-main down
ip -n "$prefix-m2" link set m2-red down
note "(detecting a dead partner by itself is the supervisor's job, next on the roadmap: here the operator asks)"
ctl red-state m1 ACTIVE | sed 's/^/   /'
sleep 2
status m1 8
slaves_in_op() { ctl status m1 | grep -cE '^ +[0-9]+ +[0-9]+ +yes +OP ' || true; }
note "slaves: $(slaves_in_op) of 5 in OP; AL transitions out of OP in ecsim: $(grep -c 'AL OP -> ' "$work/ecsim.log" || true)"
if grep -q 'SM watchdog expired' "$work/ecsim.log"; then
  # Real slaves do this too: no process data for longer than their SM watchdog (100 ms).
  note "nobody sent process data for longer than the slaves' SM watchdog (100 ms) while the operator"
  note "asked: they fell to SAFEOP+ERR 0x001B, as real slaves do. m1 acknowledges and brings them back:"
  ctl state m1 SAFEOP | sed 's/^/   /'
  wait_for 10 in_state m1 "master SAFEOP" || true
  ctl state m1 OP | sed 's/^/   /'
  wait_for 10 in_state m1 "master OP" || true
  sleep 1
  note "slaves: $(slaves_in_op) of 5 in OP"
fi

step "Events"
note "m1:"; sed 's/^/     /' "$work/events-m1.log" | grep -vE 'slave-presence' | tail -15
note "m2:"; sed 's/^/     /' "$work/events-m2.log" | grep -vE 'slave-presence' | tail -10

kill "$sim"; wait "$sim" 2>/dev/null || true; sim=
step "The segment's capture: $(tshark -r "$work/segment.pcap" -Y 'eth.type == 0x88a4' 2>/dev/null | wc -l) EtherCAT frames, $(tshark -r "$work/segment.pcap" -Y '(eth.type == 0x88a4 || ecatf) && _ws.malformed' 2>/dev/null | wc -l) malformed (tshark)"
if [ -x "$bin/bench/ecpair-capture-analysis" ]; then
  "$bin/bench/ecpair-capture-analysis" gaps "$work/segment.pcap" | sed 's/^/   /'
fi
