#!/usr/bin/env bash
# Redundancy figures on veth, in network namespaces:
#   1. the store-and-forward delay the INACTIVE adds (p50/p99/max, from the
#      timestamps of the same frame arriving at one of its adapters and
#      leaving by the other), on both of its paths (user space, then the
#      kernel's BPF program: redundancy.forwarding USER and KERNEL), and the
#      same for a plain kernel bridge between the same two veths, measured
#      right after in the same run;
#   2. the takeover gap by API: `ecpairctl red-state INACTIVE` on the ACTIVE
#      then `red-state ACTIVE` on its partner, COUNT times back and forth; the
#      gap is the time on the bus between the old ACTIVE's last process-data
#      frame and the new one's first, from ecsim's capture of the segment.
#
#   bash bench/redundancy_bench.sh [SECONDS] [COUNT]   (defaults: 10 10)
# Needs root and a build in ./build (or ECPAIR_BUILD_DIR).
#
# ecsim runs on core 0 and m2 on core 1 (REDBENCH_PIN=0: wherever the
# scheduler puts them). veth forwards in the sender's context, so the frames
# coming back from the slaves cross m2's BPF program (or the bridge) on
# ecsim's core. Unpinned, m2's cycle thread often shares that core, and as a
# standby it wakes a sixteenth of a cycle after the ACTIVE's cycle start:
# just as those frames pass. Its timer interrupt (15-20 µs in this VM) lands
# in the middle of their forwarding, and its cycle (SCHED_FIFO 80) then
# preempts ecsim's (70) send loop; the bridge run has no m2 and so none of
# that. On two controllers and a real segment the INACTIVE's cycle never runs
# on the simulator's core; the pinning makes the bench measure the forwarding.
set -euo pipefail
cd "$(dirname "$0")/.."
source deploy/lib/topology.sh
source deploy/lib/pair_member.sh
source bench/pair_bench_lib.sh
seconds=${1:-10}
count=${2:-10}
bin=${ECPAIR_BUILD_DIR:-$(pwd)/build}
eni=$(pwd)/tests/data/eni/twincat_kpierczy_5slaves.xml
prefix=ecpr$$
work=$(mktemp -d /tmp/ecpair-redbench.XXXXXX)
ctl=$bin/supervisor/ecpairctl/ecpairctl
analysis=$bin/bench/ecpair-capture-analysis

trap pair_bench_cleanup EXIT

sim_pin=()
if [ "${REDBENCH_PIN:-1}" = 1 ]; then
  sim_pin=(taskset -c 0)
  PAIR_M2_CPUS=${PAIR_M2_CPUS:-1}
fi

capture() {  # ns interface file   (tshark's messages in file.log, shown if it fails)
  ( ip netns exec "$1" tshark -q -i "$2" -f 'ether proto 0x88a4' -a "duration:$seconds" -w "$3" >"$3.log" 2>&1 ||
    { cat "$3.log" >&2; exit 1; } ) &
}

topology_up "$prefix" pair
ip netns exec "$prefix-sim" "${sim_pin[@]}" "$bin/sim/segment/ecsim" --eni "$eni" --main-if sim-main --red-if sim-red \
  --control "$work/ecsim.sock" --pcap "$work/segment.pcap" --realtime-priority 70 --log-level warn >"$work/ecsim.log" 2>&1 &
sim=$!
for _ in $(seq 100); do [ -S "$work/ecsim.sock" ] && break; sleep 0.1; done
pair_bench_member m1 ACTIVE; m1=$!
PAIR_FORWARDING=USER pair_bench_member m2 INACTIVE; m2=$!
pair_bench_wait_for "$work/m1.sock" "master OP"
pair_bench_wait_for "$work/m2.sock" "partner seen, mirrored"

pinned_cores() {  # pid
  taskset -cp "$1" | sed 's/.*: //'
}
saf_delay() {  # path
  echo "== store-and-forward delay of the INACTIVE (m2), $1 path, ${seconds} s at 1 ms"
  echo "   ecsim on core(s) $(pinned_cores "$sim"), m2 on $(pinned_cores "$m2")"
  "$ctl" status --socket "$work/m2.sock" | grep -o "store-and-forward ([a-z ]*)" | sed 's/^/   /'
  capture "$prefix-m2" m2-red "$work/inactive-red.pcap"; a=$!
  capture "$prefix-m2" m2-main "$work/inactive-main.pcap"; b=$!
  wait $a $b
  echo "   slaves -> m2 RED -> m2 MAIN -> m1 RED:"
  "$analysis" delay "$work/inactive-red.pcap" "$work/inactive-main.pcap" | sed 's/^/     /'
  echo "   m1 RED -> m2 MAIN -> m2 RED -> slaves:"
  "$analysis" delay "$work/inactive-main.pcap" "$work/inactive-red.pcap" | sed 's/^/     /'
}
saf_delay user
kill "$m2"; wait "$m2" 2>/dev/null || true; m2=
PAIR_FORWARDING=KERNEL pair_bench_member m2 INACTIVE; m2=$!
pair_bench_wait_for "$work/m2.sock" "partner seen, mirrored"
pair_bench_wait_for "$work/m2.sock" "store-and-forward (kernel)"
saf_delay kernel
echo "   load average: $(cut -d' ' -f1-3 /proc/loadavg)"

echo "== the same veths joined by a kernel bridge instead of m2 (ecsim on core(s) $(pinned_cores "$sim"))"
kill "$m2"; wait "$m2" 2>/dev/null || true; m2=
# m2's link guard took its links down as it stopped: up again for the bridge.
ip -n "$prefix-m2" link set m2-main up
ip -n "$prefix-m2" link set m2-red up
ip -n "$prefix-m2" link add name br0 type bridge
ip -n "$prefix-m2" link set m2-main master br0
ip -n "$prefix-m2" link set m2-red master br0
ip -n "$prefix-m2" link set br0 up
sleep 1
capture "$prefix-m2" m2-red "$work/bridge-red.pcap"; a=$!
capture "$prefix-m2" m2-main "$work/bridge-main.pcap"; b=$!
wait $a $b
echo "   m2-red -> m2-main:"
"$analysis" delay "$work/bridge-red.pcap" "$work/bridge-main.pcap" | sed 's/^/     /'
echo "   m2-main -> m2-red:"
"$analysis" delay "$work/bridge-main.pcap" "$work/bridge-red.pcap" | sed 's/^/     /'
ip -n "$prefix-m2" link del br0

echo "== takeover gap by API, $count switchovers (red-state INACTIVE on the ACTIVE, then ACTIVE on its partner)"
pair_bench_member m2 INACTIVE; m2=$!
pair_bench_wait_for "$work/m2.sock" "partner seen, mirrored"
active=m1; standby=m2
for _ in $(seq "$count"); do
  "$ctl" red-state --socket "$work/$active.sock" INACTIVE >/dev/null
  "$ctl" red-state --socket "$work/$standby.sock" ACTIVE >/dev/null
  pair_bench_wait_for "$work/$active.sock" "partner seen, mirrored"
  tmp=$active; active=$standby; standby=$tmp
  sleep 0.5
done
"$ctl" status --socket "$work/$active.sock" | sed -n '1,5p' | sed 's/^/   /'
kill "$sim"; wait "$sim" 2>/dev/null || true; sim=
"$analysis" gaps "$work/segment.pcap" | sed 's/^/   /'
