# Network namespaces and veth cables for ecpair on one machine (design.md §1):
#   <prefix>-sim  ecsim, the slave chain      (sim-main, sim-red)
#   <prefix>-m1   controller 1                (m1-main, m1-red)
#   <prefix>-m2   controller 2 (pair only)    (m2-main, m2-red)
# Cables: m1-main <-> sim-main; single: m1-red <-> sim-red;
#         pair: m1-red <-> m2-main (master-master) and m2-red <-> sim-red.
# Source this file; every function is safe to call twice.

topology_up() {  # prefix single|pair
  local p=$1 mode=$2
  local namespaces=("$p-sim" "$p-m1")
  [ "$mode" = pair ] && namespaces+=("$p-m2")
  for ns in "${namespaces[@]}"; do
    ip netns add "$ns" 2>/dev/null || true
    ip -n "$ns" link set lo up
    # No IPv6 chatter on the cables: only EtherCAT travels there.
    ip netns exec "$ns" sysctl -q -w net.ipv6.conf.default.disable_ipv6=1 net.ipv6.conf.all.disable_ipv6=1 >/dev/null
  done
  cable "$p-m1" m1-main "$p-sim" sim-main
  if [ "$mode" = pair ]; then
    cable "$p-m1" m1-red "$p-m2" m2-main
    cable "$p-m2" m2-red "$p-sim" sim-red
  else
    cable "$p-m1" m1-red "$p-sim" sim-red
  fi
  wait_for_carrier "$p-sim" sim-main sim-red
}

# The kernel reports carrier changes with up to a second of delay (linkwatch):
# wait until the cable ends are operational before anything uses them.
wait_for_carrier() {  # ns if...
  local ns=$1; shift
  for _ in $(seq 50); do
    local all_up=1
    for i in "$@"; do
      [ "$(ip netns exec "$ns" cat "/sys/class/net/$i/operstate" 2>/dev/null)" = up ] || all_up=0
    done
    [ $all_up = 1 ] && return 0
    sleep 0.1
  done
  echo "topology: $* in $ns did not come up" >&2
  return 1
}

cable() {  # ns_a if_a ns_b if_b
  ip -n "$1" link show "$2" >/dev/null 2>&1 && return 0
  ip -n "$1" link add name "$2" type veth peer name "$4" netns "$3"
  ip -n "$1" link set "$2" up
  ip -n "$3" link set "$4" up
}

topology_down() {  # prefix
  local p=$1
  for ns in "$p-sim" "$p-m1" "$p-m2"; do
    ip netns pids "$ns" 2>/dev/null | xargs -r kill 2>/dev/null || true
    ip netns del "$ns" 2>/dev/null || true
  done
}
