#!/usr/bin/env bash
# Multi-host test: the server, an offscreen viewer and the client, each on its own network
# host (a Linux network namespace), talking over TLS with tokens on a private subnet.
#
#   deploy/multihost/run.sh [--server-bin P] [--client-bin P] [--viewer-bin P]
#                           [--skip-viewer | --require-viewer] [--realtime X] [--keep]
#
#   --server-bin, --client-bin, --viewer-bin   the binaries (default: build/ of the checkout)
#   --skip-viewer     server and client only (no probes to check)
#   --require-viewer  fail (rather than run without it) when the viewer binary is missing
#                     or does not support --follow yet
#   --realtime X      run pacing (default 4: the 20 s seed run takes 5 s)
#   --keep            keep the temporary directory (certificates, logs, results)
#
# Layout: namespace mbs-br-<pid> holds a bridge; mbs-srv-<pid> (10.213.0.1, server),
# mbs-view-<pid> (10.213.0.2, viewer) and mbs-cli-<pid> (10.213.0.3, client) each reach it
# by a veth pair. Certificates and tokens come from deploy/make-secrets.sh (server SAN =
# IP:10.213.0.1) in a temporary directory. The client runs deploy/demo-client.sh, the same
# script as the compose demo's client. Checks: every frame of the run has a viewer probe
# within 1e-6 m of the TCP (deploy/multihost/check_probes.py), the viewer and client exit 0,
# the server exits 0 on SIGTERM. Namespaces, processes and the temporary directory are
# removed on every exit path. Needs root and `ip netns`; exits 77 (skipped) without them.
set -euo pipefail

here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
root=$(cd "$here/../.." && pwd)
server_bin=$root/build/server/app/mbstream-server
client_bin=$root/build/client/mbstream
viewer_bin=$root/build/viewer/app/mbstream-viewer
viewer_mode=auto  # auto | skip | require
realtime=4
keep=0
while [ $# -gt 0 ]; do
  case "$1" in
    --server-bin) server_bin=$2; shift 2 ;;
    --client-bin) client_bin=$2; shift 2 ;;
    --viewer-bin) viewer_bin=$2; shift 2 ;;
    --skip-viewer) viewer_mode=skip; shift ;;
    --require-viewer) viewer_mode=require; shift ;;
    --realtime) realtime=$2; shift 2 ;;
    --keep) keep=1; shift ;;
    -h|--help) sed -n '2,24p' "$0" | sed 's/^# \{0,1\}//'; exit 0 ;;
    *) echo "multihost: unknown argument $1 (see --help)" >&2; exit 2 ;;
  esac
done

log() { echo "multihost: $*"; }
skip() { echo "multihost: SKIPPED: $*"; exit 77; }
fail() { echo "multihost: FAIL: $*" >&2; exit 1; }

# ---- preconditions -------------------------------------------------------------------
. "$here/../netns-hosts.sh"
netns_preconditions
command -v openssl >/dev/null || fail "openssl not found (scripts/setup.sh installs it)"
[ -x /usr/bin/python3 ] || fail "/usr/bin/python3 not found"
for b in "$server_bin" "$client_bin"; do
  [ -x "$b" ] || fail "$b is not an executable; build it or pass --server-bin/--client-bin"
done
server_bin=$(realpath "$server_bin") client_bin=$(realpath "$client_bin")
if [ "$viewer_mode" != skip ]; then
  why=""
  if [ ! -x "$viewer_bin" ]; then
    why="$viewer_bin is not an executable"
  elif ! grep -q -- '--follow' <<<"$("$viewer_bin" --help 2>&1)"; then
    why="$viewer_bin has no --follow option yet"
  elif ! command -v xvfb-run >/dev/null; then
    why="xvfb-run is not installed (scripts/setup.sh installs xvfb)"
  fi
  if [ -n "$why" ]; then
    [ "$viewer_mode" = require ] && fail "$why"
    log "WARNING: $why: running server and client only, probes are NOT checked"
    viewer_mode=skip
  else
    viewer_bin=$(realpath "$viewer_bin")
    viewer_mode=run
  fi
fi

# ---- cleanup, on every exit path -------------------------------------------------------
id=$$
ns_br=mbs-br-$id ns_srv=mbs-srv-$id ns_view=mbs-view-$id ns_cli=mbs-cli-$id
tmp=""
netns_cleanup_on_exit

tmp=$(mktemp -d /tmp/mbs-multihost.XXXXXX)
secrets=$tmp/secrets out=$tmp/out
mkdir -p "$out"

# ---- network: a bridge host and three hosts on 10.213.0.0/24 ---------------------------
subnet=10.213.0
srv_ip=$subnet.1 view_ip=$subnet.2 cli_ip=$subnet.3
port=50051
server_addr=$srv_ip:$port

netns_bridge "$ns_br"
netns_host "$ns_srv" p-srv "$srv_ip"
netns_host "$ns_view" p-view "$view_ip"
netns_host "$ns_cli" p-cli "$cli_ip"
log "hosts: server $srv_ip ($ns_srv), viewer $view_ip ($ns_view), client $cli_ip ($ns_cli)"

# ---- secrets ------------------------------------------------------------------------------
"$root/deploy/make-secrets.sh" "$secrets" --san "IP:$srv_ip" --web-san "IP:$view_ip" >/dev/null
log "made a throwaway CA, a server certificate for IP:$srv_ip and tokens in $secrets"

# ---- server -------------------------------------------------------------------------------
ip netns exec "$ns_srv" "$server_bin" --listen "$server_addr" --data "$tmp/data" \
  --tls-cert "$secrets/server.pem" --tls-key "$secrets/server.key" \
  --token-file "$secrets/tokens" >"$tmp/server.out" 2>"$tmp/server.err" &
server_pid=$!
for _ in $(seq 1 100); do
  grep -q '^listening on' "$tmp/server.out" 2>/dev/null && break
  kill -0 "$server_pid" 2>/dev/null || { cat "$tmp/server.err" >&2; fail "the server exited at start"; }
  sleep 0.1
done
grep -q '^listening on' "$tmp/server.out" || fail "the server did not print 'listening on' in 10 s"
log "server: $(grep -m1 '^listening on' "$tmp/server.out") (TLS, tokens)"

reachable() { netns_reachable "$1" "$srv_ip" "$port"; }  # reachable NAMESPACE: the server
reachable "$ns_cli" || fail "the client host cannot reach $server_addr"

# ---- viewer -------------------------------------------------------------------------------
viewer_pid=""
if [ "$viewer_mode" = run ]; then
  reachable "$ns_view" || fail "the viewer host cannot reach $server_addr"
  ip netns exec "$ns_view" xvfb-run -a "$viewer_bin" --server "$server_addr" --follow \
    --offscreen --ca "$secrets/ca.pem" --token-file "$secrets/viewer.token" \
    --exit-after-runs 1 --record "$out/robot.ogv" --snapshots "$out/snapshots" \
    --web "$view_ip:8443" --web-tls "$secrets/web.pem,$secrets/web.key" \
    --web-root "$root/viewer/web" >"$tmp/viewer.out" 2>"$tmp/viewer.err" &
  viewer_pid=$!
  # The viewer sees a run's every frame only when it follows before the run starts: wait
  # for its "subscribed to ADDR: follow" line (the server has registered the subscription).
  connected=0
  for _ in $(seq 1 200); do
    kill -0 "$viewer_pid" 2>/dev/null || { cat "$tmp/viewer.err" >&2; fail "the viewer exited at start"; }
    if grep -qs "subscribed to" "$tmp/viewer.out" "$tmp/viewer.err"; then
      connected=1
      break
    fi
    sleep 0.1
  done
  [ "$connected" -eq 1 ] || fail "the viewer did not subscribe to $server_addr within 20 s"
  log "viewer: following runs on $server_addr from $view_ip (offscreen under Xvfb)"
  # Its web view over HTTPS from the client's host, the certificate checked against the CA.
  web_url=$(sed -n 's/^web on //p' "$tmp/viewer.out" | head -n1)
  [ "$web_url" = "https://$view_ip:8443/" ] || fail "the viewer printed 'web on ${web_url:-nothing}', not https://$view_ip:8443/"
  ip netns exec "$ns_cli" /usr/bin/python3 -c '
import ssl, sys, urllib.request
page = urllib.request.urlopen(sys.argv[1], context=ssl.create_default_context(cafile=sys.argv[2]), timeout=10).read()
sys.exit(0 if b"/page.js" in page else 1)' "$web_url" "$secrets/ca.pem" ||
    fail "the client host could not fetch the viewer's web page $web_url over HTTPS"
  log "viewer: web page served on $web_url (TLS, certificate for IP:$view_ip)"
fi

# ---- client -------------------------------------------------------------------------------
log "client: submit models/irb1600, run models/irb1600/seed-run.json at --realtime $realtime"
started=$(date +%s.%N)
set +e
ip netns exec "$ns_cli" env MBSTREAM_SERVER="$server_addr" MBSTREAM_CA="$secrets/ca.pem" \
  MBSTREAM_TOKEN_FILE="$secrets/client.token" MBSTREAM_REALTIME="$realtime" \
  MBSTREAM_CLI="$client_bin" \
  "$root/deploy/demo-client.sh" "$root/models/irb1600" "$root/models/irb1600/seed-run.json" \
  "$out/results" >"$tmp/client.out" 2>"$tmp/client.err"
client_rc=$?
set -e
elapsed=$(awk -v a="$started" -v b="$(date +%s.%N)" 'BEGIN { printf "%.1f", b - a }')
sed 's/^/  client: /' "$tmp/client.err"
[ "$client_rc" -eq 0 ] || fail "the client exited with $client_rc"
run_id=$(tail -n1 "$tmp/client.out")
log "client: run $run_id finished in $elapsed s, results in $out/results"

# ---- viewer exit, late probes ------------------------------------------------------------
viewer_rc="not run"
if [ -n "$viewer_pid" ]; then
  for _ in $(seq 1 150); do kill -0 "$viewer_pid" 2>/dev/null || break; sleep 0.1; done
  if kill -0 "$viewer_pid" 2>/dev/null; then
    sed 's/^/  viewer: /' "$tmp/viewer.err" | tail -n 20
    fail "the viewer did not exit within 15 s of the run's end (--exit-after-runs 1)"
  fi
  set +e; wait "$viewer_pid"; viewer_rc=$?; set -e
  if [ "$viewer_rc" -ne 0 ]; then
    sed 's/^/  viewer: /' "$tmp/viewer.err" | tail -n 20
    fail "the viewer exited with $viewer_rc"
  fi
  # Fetch the result again: probes that arrived after the client's download are in it.
  ip netns exec "$ns_cli" "$client_bin" --server "$server_addr" --ca "$secrets/ca.pem" \
    --token-file "$secrets/client.token" result "$run_id" --out "$out/final" \
    2>"$tmp/result.err" || { cat "$tmp/result.err" >&2; fail "mbstream result failed"; }
fi

# ---- server exit ------------------------------------------------------------------------
kill -TERM "$server_pid"
for _ in $(seq 1 100); do kill -0 "$server_pid" 2>/dev/null || break; sleep 0.1; done
kill -0 "$server_pid" 2>/dev/null && fail "the server did not stop within 10 s of SIGTERM"
set +e; wait "$server_pid"; server_rc=$?; set -e
[ "$server_rc" -eq 0 ] || { tail -n 20 "$tmp/server.err" >&2; fail "the server exited with $server_rc on SIGTERM"; }

# ---- checks -------------------------------------------------------------------------------
frames=$(($(wc -l <"$out/results/tcp.csv") - 1))
[ "$frames" -eq 401 ] || fail "tcp.csv has $frames frames, expected 401"
probes="not checked (no viewer)"
if [ "$viewer_mode" = run ]; then
  probes=$(/usr/bin/python3 "$here/check_probes.py" "$out/final" --frames 401 --tol 1e-6) ||
    { echo "$probes" >&2; fail "probe check"; }
  recorded="video $( [ -s "$out/robot.ogv" ] && echo "$(stat -c %s "$out/robot.ogv") bytes" || echo missing), $(find "$out/snapshots" -type f 2>/dev/null | wc -l) snapshots"
fi

echo "multihost: ---- summary ----"
echo "multihost: server  $server_addr TLS+tokens in $ns_srv: exit $server_rc on SIGTERM"
if [ "$viewer_mode" = run ]; then
  echo "multihost: viewer  $view_ip in $ns_view: exit $viewer_rc ($recorded)"
  echo "multihost:         $(grep -h 'viewer done' "$tmp/viewer.out" "$tmp/viewer.err" | tail -n1 | sed 's/^\[[^]]*\] \[[a-z]*\] //')"
else
  echo "multihost: viewer  not run"
fi
echo "multihost: client  $cli_ip in $ns_cli: exit $client_rc, run $run_id, $frames frames in $elapsed s"
echo "multihost: ${probes}"
if [ "$viewer_mode" = run ]; then
  echo "multihost: PASS"
else
  echo "multihost: PASS (server and client only; the viewer was not run)"
fi
