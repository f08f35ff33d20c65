#!/usr/bin/env bash
# TAP bridge figures on veth, in network namespaces (issue 9): the pair on
# ecsim's 5 slaves, each ecpaird with a TAP (m1 10.77.0.1 ACTIVE, m2
# 10.77.0.2 INACTIVE), at 1 ms and at 250 µs:
#   1. TCP throughput each way (SECONDS of bulk send, the receiver times
#      from the first byte to the end) against the ceiling
#      frames per cycle x 1446 IP bytes per frame x cycles per second;
#   2. ping RTT each way (COUNT echoes, 10 ms apart), p50/p99 in cycles.
#
#   bash bench/tap_bridge_bench.sh [SECONDS] [FRAMES_PER_CYCLE] [COUNT]   (defaults: 10 2 300)
# Needs root and a build in ./build (or ECPAIR_BUILD_DIR).
set -euo pipefail
cd "$(dirname "$0")/.."
source deploy/lib/topology.sh
source deploy/lib/pair_member.sh
seconds=${1:-10}
frames=${2:-2}
count=${3:-300}
bin=${ECPAIR_BUILD_DIR:-$(pwd)/build}
eni=$(pwd)/tests/data/eni/twincat_kpierczy_5slaves.xml
prefix=ecpt$$
work=$(mktemp -d /tmp/ecpair-tapbench.XXXXXX)
ctl=$bin/supervisor/ecpairctl/ecpairctl
probe=$bin/bench/ecpair-tcp-probe
mtu=1446

stop_pair() {
  for pid in ${m1:-} ${m2:-} ${sim:-}; do kill "$pid" 2>/dev/null && wait "$pid" 2>/dev/null || true; done
  m1= m2= sim=
}
cleanup() {
  stop_pair
  topology_down "$prefix"
  rm -rf "$work"
}
trap cleanup EXIT

member() {  # name initial-state address cycle-us
  pair_member_config "$1" "$2" "$eni" "$work" "demo { kind: WALKING_BIT }" \
    "log_level: \"warn\"
max_acyclic_frames_per_cycle: $frames
tap { name: \"ecpair0\" address: \"$3/24\" }" | sed "s/cycle_time_us: 1000/cycle_time_us: $4/" >"$work/$1.textproto"
  ip netns exec "$prefix-$1" "$bin/supervisor/ecpaird/ecpaird" --config "$work/$1.textproto" >"$work/$1.log" 2>&1 &
}
wait_for() {  # socket pattern
  for _ in $(seq 300); do "$ctl" status --socket "$1" 2>/dev/null | grep -q "$2" && return 0; sleep 0.1; done
  echo "timed out waiting for '$2' on $1" >&2; return 1
}

tcp() {  # from-ns to-ns to-address port ceiling-bytes-per-s
  ip netns exec "$2" "$probe" listen "$3" "$4" >"$work/tcp.out" &
  local listener=$!
  sleep 0.3
  ip netns exec "$1" "$probe" send "$3" "$4" "$seconds"
  wait "$listener"
  read -r _ bytes _ secs _ <"$work/tcp.out"
  awk -v b="$bytes" -v s="$secs" -v c="$5" \
    'BEGIN { r = b / s; printf "%8.0f kB/s  (%5.1f %% of the ceiling %.0f kB/s, %d bytes in %.2f s)\n", r / 1000, 100 * r / c, c / 1000, b, s }'
}

rtt() {  # from-ns to-address cycle-us
  ip netns exec "$1" ping -n -c "$count" -i 0.01 "$2" >"$work/ping.out" 2>&1 || true
  grep -o 'time=[0-9.]*' "$work/ping.out" | cut -d= -f2 | sort -n | awk -v c="$3" -v sent="$count" '
    { t[NR] = $1 }
    END { if (NR == 0) { print "no replies"; exit }
          p50 = t[int(NR * 0.50 + 0.5)]; p99 = t[int(NR * 0.99 + 0.5)]; max = t[NR]
          printf "p50 %.2f ms = %.1f cycles, p99 %.2f ms = %.1f cycles, max %.2f ms (%d of %d replies)\n",
                 p50, p50 * 1000 / c, p99, p99 * 1000 / c, max, NR, sent }'
}

topology_up "$prefix" pair
for cycle in 1000 250; do
  ip netns exec "$prefix-sim" "$bin/sim/segment/ecsim" --eni "$eni" --main-if sim-main --red-if sim-red \
    --control "$work/ecsim.sock" --realtime-priority 70 --log-level warn >"$work/ecsim.log" 2>&1 &
  sim=$!
  for _ in $(seq 100); do [ -S "$work/ecsim.sock" ] && break; sleep 0.1; done
  member m1 ACTIVE 10.77.0.1 "$cycle"; m1=$!
  member m2 INACTIVE 10.77.0.2 "$cycle"; m2=$!
  wait_for "$work/m1.sock" "ACTIVE, flowing"
  wait_for "$work/m2.sock" "INACTIVE, flowing"
  ceiling=$((frames * mtu * 1000000 / cycle))
  echo "== cycle $cycle µs, $frames bridge frames per cycle: ceiling $((ceiling / 1000)) kB/s of IP"
  printf '   TCP m1 (ACTIVE) -> m2:   '; tcp "$prefix-m1" "$prefix-m2" 10.77.0.2 7801 "$ceiling"
  printf '   TCP m2 (INACTIVE) -> m1: '; tcp "$prefix-m2" "$prefix-m1" 10.77.0.1 7802 "$ceiling"
  printf '   ping m1 -> m2: '; rtt "$prefix-m1" 10.77.0.2 "$cycle"
  printf '   ping m2 -> m1: '; rtt "$prefix-m2" 10.77.0.1 "$cycle"
  "$ctl" status --socket "$work/m1.sock" | grep -A3 'tap bridge' | sed 's/^/   m1/'
  "$ctl" status --socket "$work/m2.sock" | grep -A3 'tap bridge' | sed 's/^/   m2/'
  "$ctl" status --socket "$work/m1.sock" | grep -E '^  cycles|^  frames' | sed 's/^/   m1/'
  stop_pair
  rm -f "$work"/*.sock
done
