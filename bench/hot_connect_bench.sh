#!/usr/bin/env bash
# Hot-Connect figures on veth, in network namespaces: a single master with
# cable redundancy at 1 ms on a generated segment (3 slaves in a line, one
# Hot-Connect group of 4 slaves at junction 1's port D, identified by its
# station alias). COUNT times: the group is powered off (the change is
# waited for), then on; measured from the logs' timestamps (ms):
#   - power-on -> topology-change-done (the master's event),
#   - power-on -> the group's last slave in OP (ecsim's AL state log);
# and from ecsim's capture of the segment, for the whole window from the
# power-on to the group in OP: the cyclic frames' largest gap at the slaves,
# the cycles missing, and the LRD WKC range (the 3 slaves that stay count
# 3 in it: it must never drop below that); and the same for the 300 ms of
# steady OP right before the power-on, to tell a busy machine from the change.
# Done twice: a group of simple I/O slaves, then a group of CoE drives (a
# mailbox and three SDO InitCmds each).
#
#   bash bench/hot_connect_bench.sh [COUNT]   (default 5)
# Needs root and a build in ./build (or ECPAIR_BUILD_DIR).
set -euo pipefail
cd "$(dirname "$0")/.."
source deploy/lib/topology.sh
count=${1:-5}
bin=${ECPAIR_BUILD_DIR:-$(pwd)/build}
ctl=$bin/supervisor/ecpairctl/ecpairctl
analysis=$bin/bench/ecpair-capture-analysis
prefix=echb$$
work=$(mktemp -d /tmp/ecpair-hcbench.XXXXXX)

cleanup() {
  for pid in ${m1:-} ${sim:-}; do kill "$pid" 2>/dev/null && wait "$pid" 2>/dev/null || true; done
  topology_down "$prefix"
  rm -rf "$work"
}
trap cleanup EXIT

# "[2026-12-01 21:44:37.199] ..." -> milliseconds since the Unix epoch.
log_ms() { local stamp; stamp=$(awk -v line="$1" 'BEGIN { split(line, a, /[][]/); print a[2] }'); date -d "$stamp" +%s%3N; }
sim() { "$bin/sim/segment/ecsim" ctl --control "$work/ecsim.sock" "$@" >/dev/null; }
changes() { grep -c 'event topology-change-done' "$work/m1.log" || true; }
wait_change() {  # count before
  for _ in $(seq 200); do [ "$(changes)" -gt "$1" ] && return 0; sleep 0.05; done
  echo "no topology change done" >&2; return 1
}

run() {  # label make-eni-options...
  local label=$1; shift
  local eni=$work/$label.xml
  "$bin/sim/generator/ecsim-make-eni" --slaves 3 --groups 1 --group-slaves 4 --input-bytes 8 --output-bytes 6 "$@" -o "$eni"
  topology_up "$prefix" single
  ip netns exec "$prefix-sim" "$bin/sim/segment/ecsim" --eni "$eni" --main-if sim-main --red-if sim-red \
    --control "$work/ecsim.sock" --pcap "$work/$label.pcap" --realtime-priority 70 >"$work/ecsim.log" 2>&1 &
  sim=$!
  for _ in $(seq 100); do [ -S "$work/ecsim.sock" ] && break; sleep 0.1; done
  cat >"$work/m1.textproto" <<CONF
name: "m1"
interfaces { main: "m1-main" red: "m1-red" }
eni_path: "$eni"
cycle_time_us: 1000
cable_redundancy: true
split_lrw: true
demo { kind: WALKING_BIT }
control { path: "$work/m1.sock" }
hot_connect { detection_timeout_ms: 5000 }
CONF
  ip netns exec "$prefix-m1" "$bin/supervisor/ecpaird/ecpaird" --config "$work/m1.textproto" >"$work/m1.log" 2>&1 &
  m1=$!
  for _ in $(seq 300); do "$ctl" status --socket "$work/m1.sock" 2>/dev/null | grep -q 'master OP' && break; sleep 0.1; done
  sleep 1

  local done_ms=() op_ms=() windows=() baselines=()
  for i in $(seq "$count"); do
    local before; before=$(changes)
    sim group-off 1; wait_change "$before"; sleep 0.5
    before=$(changes)
    sim group-on 1; wait_change "$before"
    for _ in $(seq 100); do [ "$(grep -c 'Group 1 .*AL SAFEOP -> OP' "$work/ecsim.log")" -ge $((4 * (i + 1))) ] && break; sleep 0.05; done
    sleep 0.3
    local on; on=$(log_ms "$(grep 'group 1: power on' "$work/ecsim.log" | tail -1)")
    local done_at; done_at=$(log_ms "$(grep 'event topology-change-done' "$work/m1.log" | tail -1)")
    local op_at; op_at=$(log_ms "$(grep 'Group 1 .*AL SAFEOP -> OP' "$work/ecsim.log" | tail -1)")
    done_ms+=($((done_at - on)))
    op_ms+=($((op_at - on)))
    windows+=("$((on * 1000)) $(((op_at + 20) * 1000))")
    baselines+=("$(((on - 300) * 1000)) $((on * 1000))")
  done
  echo "$label: master after the runs: $("$ctl" status --socket "$work/m1.sock" | grep -E 'frames sent' | sed 's/^ *//'),"\
       "cyclic-wkc-error events: $(grep -c 'event cyclic-wkc-error' "$work/m1.log" || true)"
  kill "$m1"; wait "$m1" 2>/dev/null || true; m1=
  kill "$sim"; wait "$sim" 2>/dev/null || true; sim=
  topology_down "$prefix"

  echo "$label: power-on -> topology-change-done (ms): ${done_ms[*]}"
  echo "$label: power-on -> the group in OP (ms):       ${op_ms[*]}"
  printf '%s\n' "${done_ms[@]}" | sort -n | awk '{a[NR]=$1} END {printf "%s:   topology-change-done median %d ms, max %d ms\n", lbl, a[int((NR+1)/2)], a[NR]}' lbl="$label"
  printf '%s\n' "${op_ms[@]}" | sort -n | awk '{a[NR]=$1} END {printf "%s:   group in OP median %d ms, max %d ms\n", lbl, a[int((NR+1)/2)], a[NR]}' lbl="$label"
  for i in "${!windows[@]}"; do
    # shellcheck disable=SC2086
    echo "$label: cyclic frames at the slaves, power-on to OP: $("$analysis" cadence "$work/$label.pcap" ${windows[$i]} 1000)"
    # shellcheck disable=SC2086
    echo "$label:   the 300 ms of steady OP before:       $("$analysis" cadence "$work/$label.pcap" ${baselines[$i]} 1000)"
  done
}

run io-group
run coe-drive-group --coe-groups
