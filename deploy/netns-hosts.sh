# Network hosts for the deploy tests, sourced by deploy/multihost/run.sh and
# deploy/cluster/netns.sh: Linux network namespaces on one bridge, and their cleanup.
#
# The sourcing script defines skip (exit 77 with a reason) and sets `keep` (1: keep $tmp) and
# `tmp` (its temporary directory, "" until made); then:
#   netns_preconditions          skip unless root and `ip netns` work
#   netns_cleanup_on_exit        on every exit: stop what runs in the namespaces, delete them
#                                and $tmp (unless keep=1), keep the exit status
#   netns_bridge NAME            a namespace holding the bridge br0
#   netns_host NAME PORT IP      a namespace reaching the bridge by a veth (PORT its bridge
#                                end), eth0 with IP/24
#   netns_reachable NS IP PORT   true once a TCP connection from NS to IP:PORT works (10 s)

netns_namespaces=()
netns_bridge_ns=""

netns_preconditions() {
  [ "$(id -u)" -eq 0 ] || skip "needs root to create network namespaces (run as root)"
  command -v ip >/dev/null || skip "iproute2's ip is not installed"
  ip netns list >/dev/null 2>&1 || skip "'ip netns' does not work here"
}

netns_cleanup() {
  local rc=$?
  set +e
  trap - EXIT INT TERM
  # Whatever still runs inside our namespaces was started by the script: stop it.
  for ns in "${netns_namespaces[@]}"; do
    for pid in $(ip netns pids "$ns" 2>/dev/null); do kill -TERM "$pid" 2>/dev/null; done
  done
  for _ in $(seq 1 25); do
    local left=0
    for ns in "${netns_namespaces[@]}"; do
      [ -n "$(ip netns pids "$ns" 2>/dev/null)" ] && left=1
    done
    [ "$left" -eq 0 ] && break
    sleep 0.2
  done
  for ns in "${netns_namespaces[@]}"; do
    for pid in $(ip netns pids "$ns" 2>/dev/null); do kill -KILL "$pid" 2>/dev/null; done
  done
  wait 2>/dev/null
  for ns in "${netns_namespaces[@]}"; do ip netns del "$ns" 2>/dev/null; done
  if [ -n "$tmp" ]; then
    if [ "$keep" -eq 1 ]; then echo "kept $tmp"; else rm -rf "$tmp"; fi
  fi
  exit "$rc"
}

netns_cleanup_on_exit() {
  trap netns_cleanup EXIT
  trap 'exit 130' INT
  trap 'exit 143' TERM
}

netns_add() { ip netns add "$1"; netns_namespaces+=("$1"); ip -n "$1" link set lo up; }

netns_bridge() {
  netns_add "$1"
  netns_bridge_ns=$1
  ip -n "$1" link add br0 type bridge
  ip -n "$1" link set br0 up
}

netns_host() {
  netns_add "$1"
  ip -n "$netns_bridge_ns" link add "$2" type veth peer name eth0 netns "$1"
  ip -n "$netns_bridge_ns" link set "$2" master br0 up
  ip -n "$1" addr add "$3/24" dev eth0
  ip -n "$1" link set eth0 up
}

netns_reachable() {
  for _ in $(seq 1 100); do
    ip netns exec "$1" timeout 1 bash -c "exec 3<>/dev/tcp/$2/$3" 2>/dev/null && return 0
    sleep 0.1
  done
  return 1
}
