#!/usr/bin/env bash
# README's main command: a redundant ecpair pair on a simulated EtherCAT
# segment, all on this machine (network namespaces, veth cables). Installs
# and builds what it needs, then shows:
#   1. ecsim: the slave chain of a real ENI (TwinCAT, 5 slaves)
#   2. ecpairctl scan: the bus as an operator sees it, compared with the ENI
#   3. the pair starts with no role given: both listen, exactly one takes the
#      bus, the other stands by hot (forwards every frame, mirrors the image);
#      `ecpairctl compare` checks both images agree; the masters ping each
#      other over the TAP bridge (IP in EtherCAT frames)
#   4. a cable breaks between two slaves: the ring survives, the standby keeps
#      mirroring
#   5. `ecpairctl switchover`: the bus changes hands without a lost cycle
#   6. failover: the ACTIVE's ecpaird is killed (kill -9); its link guard takes
#      its links down, the standby's communication timeout expires and it
#      takes over hot; the restarted member comes back INACTIVE
#   7. forced standby: a member told to stand by refuses a switchover
#   8. a double line break: each half gets its ACTIVE; on repair the half
#      reaching more slaves keeps the bus, the other stands by again
#   9. the events, and the segment's capture: cycles without process data
# Run as root. ECPAIR_DEMO_ENI picks another ENI; ECPAIR_DEMO_NO_BUILD=1 skips
# the build and ECPAIR_BUILD_DIR points at another build tree; ECPAIR_DEMO_KEEP=1
# keeps the logs, configurations and the segment's capture.
set -euo pipefail
cd "$(dirname "$0")/.."
repo=$(pwd)
source deploy/lib/demo_steps.sh
source deploy/lib/topology.sh
source deploy/lib/pair_member.sh
source deploy/lib/tap_bridge.sh

eni=${ECPAIR_DEMO_ENI:-$repo/tests/data/eni/twincat_kpierczy_5slaves.xml}
bin=${ECPAIR_BUILD_DIR:-$repo/build}
prefix=ecpd$$
work=$(mktemp -d /tmp/ecpair-demo.XXXXXX)

cleanup() {
  for pid in ${events_m1:-} ${events_m2:-}; do kill "$pid" 2>/dev/null || true; done
  for pid in ${m1:-} ${m2:-} ${sim:-}; do kill "$pid" 2>/dev/null && wait "$pid" 2>/dev/null || true; done
  topology_down "$prefix"
  if [ "${ECPAIR_DEMO_KEEP:-0}" = 1 ]; then echo "logs, configs and the capture kept in $work"; else rm -rf "$work"; fi
}
trap cleanup EXIT

demo_build ecsim ecpaird ecpairctl ecpair-capture-analysis
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

step "3. The pair: m1 and m2 start at the same instant, no role given (same ENI, cable redundancy, LRW split)"
member() {  # name: starts ecpaird for pair member NAME in its namespace, prints its pid
  pair_member_config "$1" "" "$eni" "$work" "demo { kind: LOOPBACK_CHECK step_cycles: 50 }" \
    "$(tap_bridge_config "$1")" >"$work/$1.textproto"
  ip netns exec "$prefix-$1" "$ecpaird" --config "$work/$1.textproto" >>"$work/$1.log" 2>&1 &
  echo $!
}
follow_events() {  # name: appends the member's events to events-NAME.log, prints the pid
  wait_for 10 test -S "$work/$1.sock"
  ctl events "$1" >>"$work/events-$1.log" 2>&1 &
  echo $!
}
role() { ctl status "$1" 2>/dev/null | sed -n 's/^  redundancy: \([A-Z]*\).*/\1/p'; }
other() { [ "$1" = m1 ] && echo m2 || echo m1; }
settled() {  # exactly one ACTIVE with every slave in OP, the other standing by: prints the ACTIVE
  local a
  for _ in $(seq 100); do
    for a in m1 m2; do
      if [ "$(role "$a")" = ACTIVE ] && [ "$(role "$(other "$a")")" = INACTIVE ] &&
        ctl status "$a" | grep -q 'master OP' && ctl status "$(other "$a")" | grep -q 'partner seen, mirrored'; then
        echo "$a"; return 0
      fi
    done
    sleep 0.1
  done
  echo "the pair did not settle: m1 $(role m1), m2 $(role m2)" >&2
  return 1
}
supervisor() { ctl status "$1" | grep -E '^  (supervisor|partner|NO MASTER)' | sed 's/^/   /'; }
both_active() { [ "$(role m1)" = ACTIVE ] && [ "$(role m2)" = ACTIVE ]; }
out_of_op() { grep -c 'AL OP -> ' "$work/ecsim.log" || true; }

m1=$(member m1); m2=$(member m2)
events_m1=$(follow_events m1); events_m2=$(follow_events m2)
active=$(settled); standby=$(other "$active")
note "arbitration: $active took the bus, $standby heard its Cyclic Master Red Frames and stands by hot"
status "$active" 6
supervisor "$active"
note "$standby:"
ctl status "$standby" | grep -E '^  (redundancy|store-and-forward|link guard)' | sed 's/^/   /'
supervisor "$standby"
note "(master PD: the ACTIVE sends its cycle counter, the standby echoes it back)"
ctl compare "$active" --socket "$work/$standby.sock" | sed 's/^/   /'
tap_bridge_demo "$prefix" "$work" "$ecpairctl"

step "4. A cable breaks between slave 2 and slave 3 while in OP"
sim break 2 | sed 's/^/   /'
sleep 2
status "$active" 4
status "$standby" 5 | tail -2
ctl compare "$active" --socket "$work/$standby.sock" | sed 's/^/   /'
sim repair 2 | sed 's/^/   /'
sleep 1

step "5. ecpairctl switchover: $active hands the bus to $standby at an announced cycle"
ctl switchover "$active" | sed 's/^/   /'
active=$(settled); standby=$(other "$active")
sleep 1
status "$active" 6
supervisor "$active"
supervisor "$standby"
ctl compare "$active" --socket "$work/$standby.sock" | sed 's/^/   /'
note "ecsim's slaves left OP $(out_of_op) times so far"

step "6. Failover: $active's ecpaird is killed (kill -9), nobody tells $standby"
dead=$active
kill -9 "${!dead}"; wait "${!dead}" 2>/dev/null || true
note "$dead's link guard takes $dead-main and $dead-red down:" \
  "$(ip -n "$prefix-$dead" -br link show "$dead-main" | awk '{print $1, $2}'), $(ip -n "$prefix-$dead" -br link show "$dead-red" | awk '{print $1, $2}')"
wait_for 10 in_state "$standby" 'master OP' || true
status "$standby" 6
supervisor "$standby"
grep -E 'comm-timeout|takeover|red-state' "$work/events-$standby.log" | tail -3 | sed 's/^/   /'
note "slaves in OP: $(ctl status "$standby" | grep -cE '^ +[0-9]+ +[0-9]+ +yes +OP') of $(grep -c '<Slave>' "$eni"); AL transitions out of OP in ecsim: $(out_of_op)"
note "$dead's controller restarts; its link guard brings the links up and it listens first:"
declare "$dead=$(member "$dead")"
declare "events_$dead=$(follow_events "$dead")"
active=$(settled); standby=$(other "$active")
note "$active stays ACTIVE, $standby is back as hot standby (a returning master never preempts)"
supervisor "$standby"

step "7. Forced standby: $standby is told to stand by, so it may not take the bus"
ctl force-standby "$standby" | sed 's/^/   /'
note "a switchover towards it is refused, with the reason:"
ctl switchover "$active" 2>&1 | sed 's/^/   /' || true
supervisor "$standby"
ctl unforce-standby "$standby" | sed 's/^/   /'

step "8. A double line break: slave 2 -> 3 and the master-master cable"
mm_if=m1-red
sim break 2 | sed 's/^/   /'
ip -n "$prefix-m1" link set "$mm_if" down
note "m1 reaches slaves 1-2 alone, m2 slaves 3-5: each half runs under its own ACTIVE"
wait_for 10 both_active || true
sleep 1
note "m1: $(role m1), m2: $(role m2); slaves left OP $(out_of_op) times"
note "the line is repaired: the two ACTIVE masters see each other's frames (collision)"
sim repair 2 | sed 's/^/   /'
ip -n "$prefix-m1" link set "$mm_if" up
active=$(settled); standby=$(other "$active")
grep -E 'collision|arbitration-settled' "$work/events-m1.log" "$work/events-m2.log" | tail -4 | sed "s|$work/events-||; s/^/   /"
note "$active keeps the bus (its half reached more slaves); slaves left OP $(out_of_op) times in the whole demo"

step "9. Events"
events_of() { grep -vE 'slave-presence|^ecpairctl:' "$work/events-$1.log" | tail -12 | sed 's/^/     /'; }
note "m1:"; events_of m1
note "m2 (killed in step 6 and restarted):"; events_of m2

for pid in ${events_m1:-} ${events_m2:-}; do kill "$pid" 2>/dev/null || true; done
for pid in ${m1:-} ${m2:-}; do kill "$pid" 2>/dev/null && wait "$pid" 2>/dev/null || true; done
m1= m2=
kill "$sim"; wait "$sim" 2>/dev/null || true; sim=
step "The segment's capture: $(tshark -r "$work/segment.pcap" -Y 'eth.type == 0x88a4' 2>/dev/null | wc -l) EtherCAT frames, $(tshark -r "$work/segment.pcap" -Y '(eth.type == 0x88a4 || ecatf) && _ws.malformed' 2>/dev/null | wc -l) malformed (tshark)"
if [ -x "$bin/bench/ecpair-capture-analysis" ]; then
  note "cycles in which the slaves got no process data (1 ms cycle):"
  "$bin/bench/ecpair-capture-analysis" gaps "$work/segment.pcap" 1000 | sed 's/^/   /'
fi
