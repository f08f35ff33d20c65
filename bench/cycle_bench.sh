#!/usr/bin/env bash
# Long run of one ecpaird with cable redundancy on a simulated segment of 33
# slaves with ~5 kB of process data (76 bytes in + 76 out each, LWR + LRD),
# in network namespaces. Prints late cycles, lost and incomplete frames,
# wake-up latency percentiles (the cycle's jitter against its absolute
# deadline) and the CPU ecpaird and ecsim used.
#
#   bash bench/cycle_bench.sh [CYCLE_US] [SECONDS]     (defaults: 1000 600)
#
# ECPAIR_BENCH_SLAVES=N: N slaves instead of 33. ECPAIR_BENCH_CABLE_REDUNDANCY=0:
# MAIN only (ecsim gets no RED interface, so the last slave loops the frames back).
#
# Needs root and a build in ./build (or ECPAIR_BUILD_DIR).
set -euo pipefail
cd "$(dirname "$0")/.."
source deploy/lib/topology.sh
source bench/status_figures.sh
source bench/process_cpu.sh
cycle_us=${1:-1000}
seconds=${2:-600}
bin=${ECPAIR_BUILD_DIR:-$(pwd)/build}
prefix=ecpb$$
work=$(mktemp -d /tmp/ecpair-bench.XXXXXX)

cleanup() {
  for pid in ${daemon_pid:-} ${ecsim_pid:-}; do kill "$pid" 2>/dev/null && wait "$pid" 2>/dev/null || true; done
  topology_down "$prefix"
  rm -rf "$work"
}
trap cleanup EXIT


slaves=${ECPAIR_BENCH_SLAVES:-33}
"$bin/sim/generator/ecsim-make-eni" --slaves "$slaves" --input-bytes 76 --output-bytes 76 --cycle-us "$cycle_us" -o "$work/bench.xml"
topology_up "$prefix" single
redundancy=${ECPAIR_BENCH_CABLE_REDUNDANCY:-1}
if [ "$redundancy" = 1 ]; then
  sim_red=(--red-if sim-red); interfaces='main: "m1-main" red: "m1-red"'; cable_redundancy=true
else
  sim_red=(); interfaces='main: "m1-main"'; cable_redundancy=false
fi
ip netns exec "$prefix-sim" "$bin/sim/segment/ecsim" --eni "$work/bench.xml" --main-if sim-main "${sim_red[@]}" \
  --control "$work/ecsim.sock" --realtime-priority 70 --log-level warn >"$work/ecsim.log" 2>&1 &
ecsim_pid=$!
for _ in $(seq 100); do [ -S "$work/ecsim.sock" ] && break; sleep 0.1; done
cat >"$work/bench.textproto" <<CONF
name: "bench"
interfaces { $interfaces }
eni_path: "$work/bench.xml"
cycle_time_us: $cycle_us
cable_redundancy: $cable_redundancy
demo { kind: LOOPBACK_CHECK step_cycles: 10 }
control { path: "$work/bench.sock" }
log_level: "warn"
CONF
ip netns exec "$prefix-m1" "$bin/supervisor/ecpaird/ecpaird" --config "$work/bench.textproto" >"$work/ecpaird.log" 2>&1 &
daemon_pid=$!
status() { "$bin/supervisor/ecpairctl/ecpairctl" status --socket "$work/bench.sock"; }
# grep reads a captured status: piped, grep -q could end the pipe before ecpairctl finished
# writing a long status (hundreds of slaves) and pipefail would take that for "not in OP".
in_op() { grep -q 'master OP' <<<"$(status 2>/dev/null)"; }
for _ in $(seq ${ECPAIR_BENCH_OP_WAIT:-300}); do in_op && break; sleep 0.1; done
in_op || { echo "did not reach OP"; cat "$work/ecpaird.log"; exit 1; }

start_status=$(status)
start_daemon=$(process_sample "$daemon_pid"); start_sim=$(process_sample "$ecsim_pid"); start=$(date +%s.%N)
sleep "$seconds"
end_daemon=$(process_sample "$daemon_pid"); end_sim=$(process_sample "$ecsim_pid"); end=$(date +%s.%N)
end_status=$(status)


echo "cycle ${cycle_us} µs, ${seconds} s in OP, $slaves slaves, $(( slaves * 152 )) bytes of process data, cable redundancy $cable_redundancy"
print_cycle_figures
grep -E 'loopback' <<<"$end_status" | sed 's/^ */  /'
echo "  CPU ecpaird:      $(process_cpu_figures "$start_daemon" "$end_daemon" "$start" "$end")"
echo "  CPU ecsim:        $(process_cpu_figures "$start_sim" "$end_sim" "$start" "$end")"
