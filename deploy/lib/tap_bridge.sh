# The TAP bridge in the demo (issue 9): each pair member gets a TAP device
# (m1 10.77.0.1, m2 10.77.0.2) whose IP traffic travels in EtherCAT frames
# between the two controllers. Source this file.

tap_bridge_config() {  # member-name: the tap block of its configuration
  local address=10.77.0.1
  [ "$1" = m2 ] && address=10.77.0.2
  printf 'tap { name: "ecpair0" address: "%s/24" }\n' "$address"
}

tap_bridge_demo() {  # prefix work-dir ecpairctl
  local prefix=$1 work=$2 ctl=$3
  printf '   m1 pings m2 over the bridge (no cable of its own: the ping rides in EtherCAT NOP datagrams):\n'
  ip netns exec "$prefix-m1" ping -n -c 3 -i 0.2 10.77.0.2 | sed -n '2,4p;$p' | sed 's/^/     /' || true
  printf '   and m2 pings m1:\n'
  ip netns exec "$prefix-m2" ping -n -c 3 -i 0.2 10.77.0.1 | sed -n '2,4p;$p' | sed 's/^/     /' || true
  "$ctl" status --socket "$work/m1.sock" | grep -A1 'tap bridge' | sed 's/^/ /'
}
