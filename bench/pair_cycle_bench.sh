#!/usr/bin/env bash
# The pair at one cycle time (issue 12): m1 ACTIVE and m2 INACTIVE on
# ecsim's 5 slaves (TwinCAT ENI, cable redundancy, LRW split, both masters
# SCHED_FIFO), SECONDS in OP, m2 forwarding on FORWARDING (AUTO: the kernel
# where its program attaches). Prints the ACTIVE's figures of the run
# (cycles, late cycles, frames lost, incomplete cycles, the cycle thread's
# wake-up latency), m2's forwarding path, and at the slaves, from ecsim's
# capture: the cyclic frames that entered the segment, their largest gap
# (the longest time the slaves went without process data) and the cycles
# missing.
#
#   bash bench/pair_cycle_bench.sh [CYCLE_US] [SECONDS] [FORWARDING]   (defaults: 1000 20 AUTO)
# Needs root and a build in ./build (or ECPAIR_BUILD_DIR). ECSIM_PRIORITY:
# ecsim's SCHED_FIFO priority (default 70, below the masters' 78-80).
set -euo pipefail
cd "$(dirname "$0")/.."
source deploy/lib/topology.sh
source deploy/lib/pair_member.sh
source bench/pair_bench_lib.sh
source bench/status_figures.sh
source bench/process_cpu.sh
export PAIR_CYCLE_US=${1:-1000}
seconds=${2:-20}
export PAIR_FORWARDING=${3:-AUTO}
bin=${ECPAIR_BUILD_DIR:-$(pwd)/build}
eni=$(pwd)/tests/data/eni/twincat_kpierczy_5slaves.xml
prefix=ecpc$$
work=$(mktemp -d /tmp/ecpair-pairbench.XXXXXX)
ctl=$bin/supervisor/ecpairctl/ecpairctl

trap pair_bench_cleanup EXIT


topology_up "$prefix" pair
ip netns exec "$prefix-sim" "$bin/sim/segment/ecsim" --eni "$eni" --main-if sim-main --red-if sim-red \
  --control "$work/ecsim.sock" --pcap "$work/segment.pcap" --realtime-priority "${ECSIM_PRIORITY:-70}" --log-level warn >"$work/ecsim.log" 2>&1 &
sim=$!
for _ in $(seq 100); do [ -S "$work/ecsim.sock" ] && break; sleep 0.1; done
pair_bench_member m1 ACTIVE; m1=$!
pair_bench_member m2 INACTIVE; m2=$!
pair_bench_wait_for "$work/m1.sock" "master OP"
pair_bench_wait_for "$work/m2.sock" "partner seen, mirrored"
sleep 1

# m1's events of the run as they happen: its cycle stalls (cycle-stall) go
# beside the stretches the slaves went without process data.
"$ctl" events --json --for "$((seconds + 2))" --socket "$work/m1.sock" >"$work/m1-events.jsonl" 2>/dev/null &
events_pid=$!
start_status=$("$ctl" status --socket "$work/m1.sock")
start_m1=$(process_sample "$m1"); start_m2=$(process_sample "$m2"); start_sim=$(process_sample "$sim")
from_us=$(date +%s%6N)
sleep "$seconds"
to_us=$(date +%s%6N)
end_m1=$(process_sample "$m1"); end_m2=$(process_sample "$m2"); end_sim=$(process_sample "$sim")
end_status=$("$ctl" status --socket "$work/m1.sock")
seconds_of() { awk -v us="$1" 'BEGIN { printf "%.6f", us / 1e6 }'; }
cpu_of() { process_cpu_figures "$1" "$2" "$(seconds_of "$from_us")" "$(seconds_of "$to_us")"; }
forwarding=$("$ctl" status --socket "$work/m2.sock" | grep -o "store-and-forward ([a-z ]*)" || echo "store-and-forward (?)")

echo "the pair at ${PAIR_CYCLE_US} µs, ${seconds} s in OP, m2 $forwarding, load average $(cut -d' ' -f1-3 /proc/loadavg)"
echo " m1 (ACTIVE):"
print_cycle_figures
echo " CPU m1 (ACTIVE):   $(cpu_of "$start_m1" "$end_m1")"
echo " CPU m2 (INACTIVE): $(cpu_of "$start_m2" "$end_m2")"
echo " CPU ecsim:         $(cpu_of "$start_sim" "$end_sim")"
kill "$sim"; wait "$sim" 2>/dev/null || true; sim=
echo " at the slaves (cyclic frames entering the segment):"
"$bin/bench/ecpair-capture-analysis" cadence "$work/segment.pcap" "$from_us" "$to_us" "$PAIR_CYCLE_US" stretches \
  >"$work/cadence.txt"
grep -v '^stretch ' "$work/cadence.txt" | sed 's/^/  /'
wait "$events_pid" 2>/dev/null || true
# Each stretch beside the stall of m1's cycle thread that ended with it (the
# event is raised when the cycle runs again, when the frames resume): its
# wake-up latency and the deadlines it skipped; or none.
{ grep '"kind":"cycle-stall"' "$work/m1-events.jsonl" || true; } |
  sed -E 's/.*"unix_time_ms":([0-9]+).*"text":"[^"]*: ([0-9]+) cycle deadline\(s\)[^"]*woke ([0-9]+) .*/\1 \2 \3/' >"$work/stalls.txt"
awk -v cycle_us="$PAIR_CYCLE_US" 'FILENAME == ARGV[1] { ++n; at[n] = $1 * 1000; skipped[n] = $2; late[n] = $3; next }
  /^stretch / {
    best = 0
    for (i = 1; i <= n; ++i) {
      d = at[i] - $2; if (d < 0) d = -d
      if (d <= 2 * cycle_us + 1000 && (best == 0 || d < bestd)) { best = i; bestd = d }
    }
    if (best) printf "  stretch of %.0f us (%.1f cycles): m1 stalled, woke %d us late, %d deadlines skipped\n", $3, $3 / cycle_us, late[best], skipped[best]
    else printf "  stretch of %.0f us (%.1f cycles): no stall of m1 beside it\n", $3, $3 / cycle_us
  }' "$work/stalls.txt" "$work/cadence.txt"
