# The configuration of one member of the pair in the design.md topology
# (interfaces NAME-main / NAME-red, 1 ms, cable redundancy with LRW split,
# 8 bytes of master process data each way), for the demo and the benchmarks.
# No initial role unless one is given: the members' supervisors decide
# (listen, then take over or stand by); the link guard is on (a pair's
# default). PAIR_FORWARDING=KERNEL|USER|AUTO, when set, picks the
# INACTIVE's store-and-forward path (redundancy.forwarding); PAIR_CYCLE_US
# another cycle time than 1000 µs. Source this file.

pair_member_config() {  # name initial-state|"" eni control-dir demo-line [extra-line]
  local role=""
  [ -n "$2" ] && role="initial_state: $2 "
  cat <<CONF
name: "$1"
interfaces { main: "$1-main" red: "$1-red" }
eni_path: "$3"
cycle_time_us: ${PAIR_CYCLE_US:-1000}
cable_redundancy: true
split_lrw: true
$5
control { path: "$4/$1.sock" }
redundancy { enabled: true ${role}${PAIR_FORWARDING:+forwarding: $PAIR_FORWARDING }master_pd_out_size: 8 master_pd_in_size: 8 }
${6:-}
CONF
}
