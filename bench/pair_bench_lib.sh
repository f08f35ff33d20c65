# What the pair benchmarks share (bench/redundancy_bench.sh,
# bench/pair_cycle_bench.sh): starting a member in its namespace, waiting for
# a status line, and cleaning up. Source it after deploy/lib/topology.sh and
# deploy/lib/pair_member.sh, with these set:
#   prefix  the topology's namespace prefix     work  the run's directory
#   bin     the build tree                      eni   the ENI both members load
#   ctl     ecpairctl
# and m1, m2, sim holding the pids the script started (cleanup stops them).
# PAIR_M1_CPUS / PAIR_M2_CPUS, when set, pin a member to those CPUs
# (taskset -c): two controllers on one machine, each on a core of its own.

pair_bench_cleanup() {
  for pid in ${m1:-} ${m2:-} ${sim:-}; do kill "$pid" 2>/dev/null && wait "$pid" 2>/dev/null || true; done
  topology_down "$prefix"
  rm -rf "$work"
}

pair_bench_member() {  # name initial-state   (the pid is in $!)
  pair_member_config "$1" "$2" "$eni" "$work" "demo { kind: WALKING_BIT }" 'log_level: "warn"' >"$work/$1.textproto"
  local cpus_var="PAIR_${1^^}_CPUS"
  local pin=()
  [ -n "${!cpus_var:-}" ] && pin=(taskset -c "${!cpus_var}")
  ip netns exec "$prefix-$1" "${pin[@]}" "$bin/supervisor/ecpaird/ecpaird" --config "$work/$1.textproto" \
    >"$work/$1.log" 2>&1 &
}

pair_bench_wait_for() {  # socket pattern   (30 s; the members' logs when it times out)
  for _ in $(seq 300); do grep -q "$2" <<<"$("$ctl" status --socket "$1" 2>/dev/null)" && return 0; sleep 0.1; done
  echo "timed out waiting for '$2' on $1" >&2
  cat "$work"/*.log >&2
  return 1
}
