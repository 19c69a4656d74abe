#!/usr/bin/env bash
# Prints HAProxy's configuration for the cluster (haproxy.cfg.in filled in): the address it
# listens on, its certificate-and-key file, the CA it checks the replicas with, and the
# replicas' host:port. The compose `lb` service and netns.sh both use it.
#
#   haproxy-config.sh LISTEN CERT_AND_KEY CA REPLICA...
set -euo pipefail
[ $# -ge 4 ] || { echo "usage: haproxy-config.sh LISTEN CERT_AND_KEY CA REPLICA..." >&2; exit 2; }
here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
listen=$1 cert=$2 ca=$3
shift 3
servers="" n=0
for replica in "$@"; do
  n=$((n + 1))
  servers+="  server replica$n $replica"$'\n'
done
awk -v listen="$listen" -v cert="$cert" -v ca="$ca" -v servers="$servers" '
  { gsub(/@LB_ADDRESS@/, listen); gsub(/@CERT_AND_KEY@/, cert); gsub(/@CA@/, ca) }
  $0 == "@SERVERS@" { printf "%s", servers; next }
  { print }' "${HAPROXY_TEMPLATE:-$here/haproxy.cfg.in}"
