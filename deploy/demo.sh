#!/usr/bin/env bash
# README's main command: ecpair on a simulated EtherCAT segment, all on this
# machine. Installs and builds what it needs, then shows:
#   1. ecsim: a simulated slave chain built from a real ENI, in a namespace
#   2. ecpairctl scan: the bus as an operator sees it, compared with the ENI
#   3. ecpaird: one master with cable redundancy drives the slaves to OP,
#      the demo application's outputs come back as inputs
#   4. a cable breaks between two slaves: the ring survives, no cycle lost
#   5. the cable is repaired
# Run as root. ECPAIR_DEMO_ENI picks another ENI; ECPAIR_DEMO_NO_BUILD=1 skips the
# build and ECPAIR_BUILD_DIR points at another build tree.
set -euo pipefail
cd "$(dirname "$0")/.."
repo=$(pwd)
source deploy/lib/topology.sh

eni=${ECPAIR_DEMO_ENI:-$repo/tests/data/eni/twincat_kpierczy_5slaves.xml}
bin=${ECPAIR_BUILD_DIR:-$repo/build}
prefix=ecpd$$
work=$(mktemp -d /tmp/ecpair-demo.XXXXXX)

step() { printf '\n\033[1m== %s\033[0m\n' "$*"; }
note() { printf '   %s\n' "$*"; }

cleanup() {
  [ -n "${events_pid:-}" ] && kill "$events_pid" 2>/dev/null || true
  for pid in ${daemon_pid:-} ${ecsim_pid:-}; do kill "$pid" 2>/dev/null && wait "$pid" 2>/dev/null || true; done
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
ctl() { "$ecpairctl" "$1" --socket "$work/m1.sock" "${@:2}"; }
sim() { "$ecsim" ctl --control "$work/ecsim.sock" "$@"; }

step "1. ecsim: the slaves of $(basename "$eni") on veth cables in namespace $prefix-sim"
topology_up "$prefix" single
ip netns exec "$prefix-sim" "$ecsim" --eni "$eni" --main-if sim-main --red-if sim-red \
  --control "$work/ecsim.sock" --pcap "$work/segment.pcap" --realtime-priority 70 >"$work/ecsim.log" 2>&1 &
ecsim_pid=$!
wait_for 10 test -S "$work/ecsim.sock"
sim status | tr ' ' '\n' | grep -E '^(slaves|main|red)=' | paste -sd' ' | sed 's/^/   /'

step "2. ecpairctl scan from controller 1's MAIN adapter (namespace $prefix-m1)"
ip netns exec "$prefix-m1" "$ecpairctl" scan --if m1-main --red-if m1-red --eni "$eni"

step "3. ecpaird: one master, cable redundancy on (MAIN and RED), LRW split into LWR + LRD"
cat >"$work/m1.textproto" <<CONF
name: "m1"
interfaces { main: "m1-main" red: "m1-red" }
eni_path: "$eni"
cycle_time_us: 1000
cable_redundancy: true
split_lrw: true
demo { kind: LOOPBACK_CHECK step_cycles: 50 }
control { path: "$work/m1.sock" }
CONF
ip netns exec "$prefix-m1" "$ecpaird" --config "$work/m1.textproto" >"$work/m1.log" 2>&1 &
daemon_pid=$!
wait_for 10 test -S "$work/m1.sock"
ctl events >"$work/events.log" 2>&1 &
events_pid=$!
wait_for 30 bash -c "'$ecpairctl' status --socket '$work/m1.sock' | grep -q 'master OP'" || true
sleep 1
ctl status --variables 3
note "(inputs: ecsim's slaves put a frame counter first, then echo the outputs)"
sleep 1
note "one second later:"
ctl status --variables 3 | sed -n '/inputs:/,$p'

counters() { ctl status | grep -E 'frames sent|loopback'; }
step "4. A cable breaks between slave 2 and slave 3 while in OP"
before=$(ctl status | grep -oE 'lost [0-9]+' | grep -oE '[0-9]+')
sim break 2
sleep 2
ctl status | sed -n '1,5p'
after=$(ctl status | grep -oE 'lost [0-9]+' | grep -oE '[0-9]+')
note "frames lost while broken: $((after - before)) (the merged MAIN and RED copies carry every slave's data)"

step "5. The cable is repaired"
sim repair 2
sleep 1
ctl status | sed -n '1,6p'

step "Events seen by ecpairctl events"
sed 's/^/   /' "$work/events.log"

step "Capture of the segment: $(tshark -r "$work/segment.pcap" -Y 'eth.type == 0x88a4' 2>/dev/null | wc -l) EtherCAT frames, $(tshark -r "$work/segment.pcap" -Y '(eth.type == 0x88a4 || ecatf) && _ws.malformed' 2>/dev/null | wc -l) malformed (tshark)"
note "logs: ecsim and ecpaird wrote to $work (removed at exit)"
