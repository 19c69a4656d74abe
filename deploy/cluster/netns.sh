#!/usr/bin/env bash
# The cluster without Docker: PostgreSQL, three mbstream-server replicas sharing it, HAProxy
# balancing each gRPC call over them (HTTP/2, TLS both sides), a client running a sweep and an
# offscreen viewer following through the balancer, each on its own network host (a Linux
# network namespace), with TLS and tokens as in the demo.
#
#   deploy/cluster/netns.sh [--server-bin P] [--client-bin P] [--viewer-bin P] [--skip-viewer]
#                           [--runs N] [--replicas N] [--store sqlite|postgresql] [--direct]
#                           [--client sweep|rate] [--keep]
#
#   --runs N       runs in the sweep (default 30)
#   --replicas N   server replicas (default 3, at most 9)
#   --store        the replicas' store (default postgresql; sqlite: each its own, --replicas 1)
#   --direct       no HAProxy: the client talks to the one replica (--replicas 1)
#   --client rate  instead of sweep-client.sh, sweep_rate.py: --runs short runs (1 s simulated,
#                  kinematic) on one channel, at most 48 unfinished; prints runs per second
#   --skip-viewer  no viewer host
#   --keep         keep the temporary directory (certificates, configuration, logs)
#
# Hosts on 10.214.0.0/24, each a namespace named with this script's process id: PostgreSQL
# 10.214.0.2 (mbc-pg-PID), HAProxy 10.214.0.10 (mbc-lb-PID), replicas 10.214.0.11.. (mbc-srvN-PID,
# gRPC on 50051, metrics on 9464), client 10.214.0.20 (mbc-cli-PID), viewer 10.214.0.21
# (mbc-view-PID); a bridge in mbc-br-PID joins them. The client runs sweep-client.sh (the
# compose client's script) against HAProxy. Checks: every run of the sweep FINISHED; each
# replica finished at least one of them and together exactly the sweep (each replica's
# mbstream_runs_ended_total{state="finished"} from its /metrics); before the sweep, a viewer
# following replica 1 directly answered every frame of a run integrated on replica 2 (relayed
# by replica 1; replica 2 stored the probe reports); after it, a replica killed (SIGKILL)
# during a run has that run INTERRUPTED (--lease-timeout-s 3) while the runs of the other
# replicas FINISH; the other replicas exit 0 on SIGTERM. Prints the sweep's runs per second
# and the time from the kill to INTERRUPTED. Needs root, `ip netns`, PostgreSQL and HAProxy; exits 77 (skipped) without.
set -euo pipefail

here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
root=$(cd "$here/../.." && pwd)
server_bin=$root/build/server/app/mbstream-server
client_bin=$root/build/client/mbstream
viewer_bin=$root/build/viewer/app/mbstream-viewer
viewer=1 runs=30 replicas=3 keep=0 store=postgresql direct=0 client=sweep
lease_s=3  # --lease-timeout-s: a killed replica's run is marked within 1.5 .. 3 s
while [ $# -gt 0 ]; do
  case "$1" in
    --server-bin) server_bin=$2; shift 2 ;;
    --client-bin) client_bin=$2; shift 2 ;;
    --viewer-bin) viewer_bin=$2; shift 2 ;;
    --skip-viewer) viewer=0; shift ;;
    --runs) runs=$2; shift 2 ;;
    --replicas) replicas=$2; shift 2 ;;
    --store) store=$2; shift 2 ;;
    --direct) direct=1; shift ;;
    --client) client=$2; shift 2 ;;
    --keep) keep=1; shift ;;
    -h|--help) sed -n '2,25p' "$0" | sed 's/^# \{0,1\}//'; exit 0 ;;
    *) echo "cluster: unknown argument $1 (see --help)" >&2; exit 2 ;;
  esac
done

log() { echo "cluster: $*"; }
skip() { echo "cluster: SKIPPED: $*"; exit 77; }
fail() { echo "cluster: FAIL: $*" >&2; exit 1; }

# ---- preconditions -------------------------------------------------------------------
. "$here/../netns-hosts.sh"
netns_preconditions
command -v haproxy >/dev/null || skip "haproxy is not installed (scripts/setup.sh installs it)"
pg_bin=$(ls -d /usr/lib/postgresql/*/bin 2>/dev/null | sort -V | tail -n1)
[ -x "$pg_bin/initdb" ] || skip "PostgreSQL is not installed (scripts/setup.sh installs it)"
id postgres >/dev/null 2>&1 || skip "there is no postgres account to run PostgreSQL as"
command -v curl >/dev/null || fail "curl not found"
case "$replicas" in [1-9]) ;; *) fail "--replicas takes 1 to 9" ;; esac
case "$store" in postgresql) ;; sqlite) [ "$replicas" -eq 1 ] || fail "--store sqlite takes --replicas 1" ;;
  *) fail "--store takes sqlite or postgresql" ;; esac
[ "$direct" -eq 0 ] || [ "$replicas" -eq 1 ] || fail "--direct takes --replicas 1"
case "$client" in sweep|rate) ;; *) fail "--client takes sweep or rate" ;; esac
for b in "$server_bin" "$client_bin"; do
  [ -x "$b" ] || fail "$b is not an executable; build it or pass --server-bin/--client-bin"
done
server_bin=$(realpath "$server_bin") client_bin=$(realpath "$client_bin")
grep -q -- '--metrics' <<<"$("$server_bin" --help)" || fail "$server_bin has no --metrics option"
if [ "$viewer" -eq 1 ]; then
  [ -x "$viewer_bin" ] || fail "$viewer_bin is not an executable (or give --skip-viewer)"
  command -v xvfb-run >/dev/null || fail "xvfb-run is not installed (or give --skip-viewer)"
  viewer_bin=$(realpath "$viewer_bin")
fi

# ---- cleanup, on every exit path -------------------------------------------------------
id=$$
tmp=""
netns_cleanup_on_exit

tmp=$(mktemp -d /tmp/mbs-cluster.XXXXXX)
chmod 755 "$tmp"  # PostgreSQL runs as postgres under it
secrets=$tmp/secrets
mkdir -p "$tmp/logs"

# ---- network ------------------------------------------------------------------------------
subnet=10.214.0
pg_ip=$subnet.2 lb_ip=$subnet.10 cli_ip=$subnet.20 view_ip=$subnet.21
port=50051 metrics_port=9464
lb_addr=$lb_ip:$port
ns_br=mbc-br-$id
netns_bridge "$ns_br"
ns_pg=mbc-pg-$id ns_lb=mbc-lb-$id ns_cli=mbc-cli-$id ns_view=mbc-view-$id
netns_host "$ns_pg" p-pg "$pg_ip"
netns_host "$ns_lb" p-lb "$lb_ip"
netns_host "$ns_cli" p-cli "$cli_ip"
[ "$viewer" -eq 1 ] && netns_host "$ns_view" p-view "$view_ip"
srv_ips=() srv_ns=()
san="IP:$lb_ip"
for i in $(seq 1 "$replicas"); do
  srv_ips+=("$subnet.1$i") srv_ns+=("mbc-srv$i-$id")
  netns_host "mbc-srv$i-$id" "p-srv$i" "$subnet.1$i"
  san="$san,IP:$subnet.1$i"
done
log "hosts: postgresql $pg_ip, haproxy $lb_ip, replicas ${srv_ips[*]}, client $cli_ip$([ "$viewer" -eq 1 ] && echo ", viewer $view_ip")"

# ---- secrets ------------------------------------------------------------------------------
"$here/make-secrets.sh" "$secrets" --san "$san" >/dev/null
log "made a throwaway CA, a certificate for $san, tokens and a PostgreSQL password"

# ---- PostgreSQL (or each replica its own SQLite) -------------------------------------------
if [ "$store" = postgresql ]; then
  pg=$tmp/pg
  mkdir -p "$pg" && chown postgres "$pg"
  runuser -u postgres -- "$pg_bin/initdb" -D "$pg/data" -U postgres --auth-local=trust \
    --auth-host=scram-sha-256 -E UTF8 >"$tmp/logs/initdb.log" 2>&1 || { cat "$tmp/logs/initdb.log" >&2; fail "initdb"; }
  echo "host all all $subnet.0/24 scram-sha-256" >>"$pg/data/pg_hba.conf"
  ip netns exec "$ns_pg" runuser -u postgres -- "$pg_bin/pg_ctl" -D "$pg/data" -w -s \
    -l "$pg/postgresql.log" -o "-c listen_addresses=$pg_ip -k $pg -c fsync=off -c max_connections=200" start ||
    { cat "$pg/postgresql.log" >&2; fail "PostgreSQL did not start"; }
  ip netns exec "$ns_pg" runuser -u postgres -- psql -h "$pg" -U postgres -q -v ON_ERROR_STOP=1 \
    -c "CREATE ROLE mbstream LOGIN PASSWORD '$(cat "$secrets/pg.password")'" \
    -c "CREATE DATABASE mbstream OWNER mbstream" >/dev/null
  store_uri=postgresql://mbstream@$pg_ip:5432/mbstream
  log "postgresql: $store_uri (password from a file)"
  store_args=(--store "$store_uri" --store-password-file "$secrets/pg.password")
else
  store_args=(--store "sqlite:$tmp/data")
  log "store: SQLite in $tmp/data"
fi

# ---- replicas -------------------------------------------------------------------------------
srv_pids=()
for i in $(seq 0 $((replicas - 1))); do
  ip=${srv_ips[$i]} out=$tmp/logs/server$((i + 1))
  ip netns exec "${srv_ns[$i]}" "$server_bin" --listen "$ip:$port" "${store_args[@]}" \
    --metrics "$ip:$metrics_port" \
    --models "$root/models" \
    --tls-cert "$secrets/server.pem" --tls-key "$secrets/server.key" \
    --token-file "$secrets/tokens" \
    --peer-ca "$secrets/ca.pem" --peer-tls-name "$lb_ip" --lease-timeout-s "$lease_s" \
    >"$out.out" 2>"$out.err" &
  srv_pids+=($!)
  for _ in $(seq 1 300); do
    grep -q '^metrics on' "$out.out" 2>/dev/null && break
    kill -0 "${srv_pids[$i]}" 2>/dev/null || { cat "$out.err" >&2; fail "replica $((i + 1)) exited at start"; }
    sleep 0.1
  done
  grep -q '^metrics on' "$out.out" || fail "replica $((i + 1)) did not start within 30 s"
  log "replica $((i + 1)): $(grep -m1 '^listening on' "$out.out"), $(grep -m1 '^metrics on' "$out.out")"
done

# ---- HAProxy (or, --direct, none) ------------------------------------------------------------
if [ "$direct" -eq 1 ]; then
  lb_addr=${srv_ips[0]}:$port
  log "no balancer: the client and viewer talk to replica 1 at $lb_addr"
else
  "$here/haproxy-config.sh" "$lb_addr" "$secrets/haproxy.pem" "$secrets/ca.pem" \
    $(printf "%s:$port " "${srv_ips[@]}") >"$tmp/haproxy.cfg"
  haproxy -c -q -f "$tmp/haproxy.cfg" || fail "haproxy rejected $tmp/haproxy.cfg"
  ip netns exec "$ns_lb" haproxy -db -f "$tmp/haproxy.cfg" >"$tmp/logs/haproxy.log" 2>&1 &
  lb_pid=$!
  netns_reachable "$ns_cli" "$lb_ip" "$port" || fail "the client host cannot reach HAProxy at $lb_addr"
  log "haproxy: $lb_addr, round-robin per call over $replicas replicas (HTTP/2, TLS both sides)"
fi


# ---- viewer: a run of another replica, through the replica it follows ------------------------
cli() {  # cli ADDRESS ARGS...: the CLI on the client host against ADDRESS
  local address=$1
  shift
  ip netns exec "$ns_cli" env MBSTREAM_SERVER="$address" MBSTREAM_CA="$secrets/ca.pem" \
    MBSTREAM_TOKEN_FILE="$secrets/client.token" "$client_bin" "$@"
}
owner_of() {  # owner_of RUN: the number of the replica that claimed RUN (its log says so)
  local i
  for i in $(seq 1 "$replicas"); do
    grep -qs "run $1 claimed by replica" "$tmp/logs/server$i.out" "$tmp/logs/server$i.err" &&
      { echo "$i"; return; }
  done
  echo 0
}
state_of() {  # state_of ADDRESS RUN: its state as `mbstream runs` lists it
  cli "$1" runs | awk -v id="$2" '$1 == id { print $3 }'
}
viewer_summary="not run" extra=0
if [ "$viewer" -eq 1 ] && [ "$replicas" -ge 2 ]; then
  # The viewer follows replica 1 directly; the run is started on replica 2, whose worker is
  # woken at once (replica 1 looks at the queue every 0.25 s): replica 2 integrates it and
  # replica 1 relays it to the viewer, whose probe reports go back to replica 2. Should
  # replica 1 win the claim, the viewer and the run are started again (at most 3 times).
  viewer_addr=${srv_ips[0]}:$port
  for attempt in 1 2 3; do
    # xvfb-run looks for a free display from a number of this script's own (-n), not from
    # :99 as every other test does.
    ip netns exec "$ns_view" xvfb-run -a -n $((100 + id % 800)) "$viewer_bin" --server "$viewer_addr" \
      --follow --offscreen --exit-after-runs 1 --ca "$secrets/ca.pem" \
      --token-file "$secrets/viewer.token" \
      >"$tmp/logs/viewer.out" 2>"$tmp/logs/viewer.err" &
    viewer_pid=$!
    for _ in $(seq 1 200); do
      kill -0 "$viewer_pid" 2>/dev/null || { cat "$tmp/logs/viewer.err" >&2; fail "the viewer exited at start"; }
      grep -qs "subscribed to" "$tmp/logs/viewer.out" "$tmp/logs/viewer.err" && break
      sleep 0.1
    done
    grep -qs "subscribed to" "$tmp/logs/viewer.out" "$tmp/logs/viewer.err" ||
      fail "the viewer did not subscribe to replica 1 at $viewer_addr within 20 s"
    extra=$((extra + 1))  # FINISHED runs besides the sweep's
    shown=$(cli "${srv_ips[1]}:$port" run irb1600 --spec "$root/models/irb1600/seed-run.json" \
      --duration 2 --realtime 1)
    for _ in $(seq 1 300); do kill -0 "$viewer_pid" 2>/dev/null || break; sleep 0.1; done
    kill -0 "$viewer_pid" 2>/dev/null && fail "the viewer did not end after run $shown within 30 s"
    wait "$viewer_pid" || fail "the viewer exited with $? after run $shown"
    viewer_pid=""
    owner=$(owner_of "$shown")
    [ "$owner" -ne 1 ] && break
    log "run $shown was claimed by replica 1 itself; again (attempt $attempt)"
  done
  [ "$owner" -ge 2 ] || fail "run $shown was never integrated on another replica than the viewer's"
  # "viewer done: 1 runs, last run R: F frames, P probe reports": every frame answered.
  done_line=$(cat "$tmp/logs/viewer.out" "$tmp/logs/viewer.err" | grep -m1 -o 'viewer done: .*' || true)
  read -r frames probes < <(sed -E 's/.*: ([0-9]+) frames, ([0-9]+) probe reports.*/\1 \2/' <<<"$done_line")
  [[ "$done_line" == *"last run $shown:"* ]] && [ "${frames:-0}" -gt 0 ] && [ "$frames" = "$probes" ] ||
    fail "the viewer on replica 1 did not answer every frame of run $shown (replica $owner): '$done_line'"
  # The owner stored them (replica 1 only relayed): its probe latency histogram counted them.
  stored=$(ip netns exec "$ns_cli" curl -sf "http://${srv_ips[$((owner - 1))]}:$metrics_port/metrics" |
    awk '$1 == "mbstream_probe_latency_seconds_count" { print $2 }')
  [ "${stored:-0}" -ge "$probes" ] ||
    fail "replica $owner counted ${stored:-0} probe reports of the viewer's $probes"
  viewer_summary="followed replica 1, run $shown integrated on replica $owner: $frames frames, $probes probe reports (stored by replica $owner)"
  log "viewer: $viewer_summary"
elif [ "$viewer" -eq 1 ]; then
  log "viewer: skipped (one replica: no run of another replica to follow)"
fi

# ---- the sweep ------------------------------------------------------------------------------
started=$(date +%s.%N)
set +e
if [ "$client" = sweep ]; then
  log "client: submit models/irb1600, a sweep of $runs runs through $lb_addr"
  ip netns exec "$ns_cli" env MBSTREAM_SERVER="$lb_addr" MBSTREAM_CA="$secrets/ca.pem" \
    MBSTREAM_TOKEN_FILE="$secrets/client.token" MBSTREAM_CLI="$client_bin" \
    "$here/sweep-client.sh" "$root/models/irb1600" "$root/models/irb1600/seed-run.json" "$runs" \
    >"$tmp/logs/client.out" 2>"$tmp/logs/client.err"
else
  log "client: $runs short runs of the built-in irb1600 on one channel through $lb_addr"
  mkdir -p "$tmp/stubs"
  protoc -I "$root/proto" --python_out="$tmp/stubs" --grpc_out="$tmp/stubs" \
    --plugin=protoc-gen-grpc="$(command -v grpc_python_plugin)" "$root"/proto/mbstream/v1/*.proto
  ip netns exec "$ns_cli" /usr/bin/python3 "$here/sweep_rate.py" --server "$lb_addr" \
    --ca "$secrets/ca.pem" --token-file "$secrets/client.token" --stubs "$tmp/stubs" \
    --runs "$runs" --spec "$root/models/irb1600/seed-run.json" \
    >"$tmp/logs/client.out" 2>"$tmp/logs/client.err"
fi
client_rc=$?
set -e
elapsed=$(awk -v a="$started" -v b="$(date +%s.%N)" 'BEGIN { printf "%.2f", b - a }')
sed 's/^/  client: /' "$tmp/logs/client.err"
[ "$client_rc" -eq 0 ] || { cat "$tmp/logs/client.out"; fail "the client exited with $client_rc"; }
if [ "$client" = sweep ]; then
  [ "$(wc -l <"$tmp/logs/client.out")" -eq "$runs" ] || fail "the client printed $(wc -l <"$tmp/logs/client.out") run ids, expected $runs"
else
  sed 's/^/  client: /' "$tmp/logs/client.out"
fi

# ---- spread over the replicas (each replica's own counters) -------------------------------
finished_on() {  # finished_on IP: mbstream_runs_ended_total{state="finished"} of that replica
  ip netns exec "$ns_cli" curl -sf "http://$1:$metrics_port/metrics" |
    awk '$1 == "mbstream_runs_ended_total{state=\"finished\"}" { print $2 }'
}
total=0 spread=""
for i in $(seq 0 $((replicas - 1))); do
  n=$(finished_on "${srv_ips[$i]}")
  [ -n "$n" ] || fail "replica $((i + 1)) served no metrics"
  spread+="${spread:+, }replica$((i + 1)) $n"
  total=$((total + n))
  [ "$n" -ge 1 ] || fail "replica $((i + 1)) finished no run of the sweep ($spread): not balanced"
done
[ "$total" -eq "$((runs + extra))" ] ||
  fail "the replicas finished $total runs together, the sweep had $runs (and the viewer's $extra)"
log "spread: $spread (by each replica's mbstream_runs_ended_total)"

# ---- a replica killed (SIGKILL) during a run --------------------------------------------------
# Four paced runs (8 s of wall time each, no retries) started through the balancer; once all
# run, the replica integrating the first is killed. That run must become INTERRUPTED (its
# lease expires: within --lease-timeout-s), the runs of the other replicas FINISHED.
kill_summary="not run"
if [ "$replicas" -ge 2 ]; then
  kill_ids=()
  for _ in 1 2 3 4; do
    kill_ids+=("$(cli "$lb_addr" run irb1600 --spec "$root/models/irb1600/seed-run.json" --duration 8 --realtime 1)")
  done
  for _ in $(seq 1 300); do
    listing=$(cli "$lb_addr" runs)
    running=0
    for r in "${kill_ids[@]}"; do
      [ "$(awk -v id="$r" '$1 == id { print $3 }' <<<"$listing")" = RUNNING ] && running=$((running + 1))
    done
    [ "$running" -eq 4 ] && break
    sleep 0.1
  done
  [ "$running" -eq 4 ] || fail "the four runs to kill a replica under did not all run within 30 s"
  victim=$(owner_of "${kill_ids[0]}")
  [ "$victim" -ge 1 ] || fail "no replica says it claimed run ${kill_ids[0]}"
  survivor=$(( victim == 1 ? 2 : 1 ))
  survivor_addr=${srv_ips[$((survivor - 1))]}:$port
  kill -KILL "${srv_pids[$((victim - 1))]}"
  killed_at=$(date +%s.%N)
  wait "${srv_pids[$((victim - 1))]}" 2>/dev/null || true
  for _ in $(seq 1 300); do
    [ "$(state_of "$survivor_addr" "${kill_ids[0]}")" = RUNNING ] || break
    sleep 0.05
  done
  marked=$(awk -v a="$killed_at" -v b="$(date +%s.%N)" 'BEGIN { printf "%.2f", b - a }')
  final=$(state_of "$survivor_addr" "${kill_ids[0]}")
  [ "$final" = INTERRUPTED ] ||
    fail "run ${kill_ids[0]} of the killed replica $victim is $final, not INTERRUPTED (no retries)"
  others=0 lost=0
  for r in "${kill_ids[@]:1}"; do
    for _ in $(seq 1 300); do
      state=$(state_of "$survivor_addr" "$r")
      case "$state" in QUEUED|RUNNING|"") sleep 0.1 ;; *) break ;; esac
    done
    if [ "$(owner_of "$r")" -eq "$victim" ]; then
      lost=$((lost + 1))  # also on the killed replica: INTERRUPTED as well
      [ "$state" = INTERRUPTED ] || fail "run $r of the killed replica $victim is $state"
    else
      others=$((others + 1))
      [ "$state" = FINISHED ] || fail "run $r of replica $(owner_of "$r") is $state after replica $victim was killed"
    fi
  done
  [ "$others" -ge 1 ] || fail "all four runs were on replica $victim: nothing shows the others unaffected"
  kill_summary="replica $victim killed during run ${kill_ids[0]}: INTERRUPTED $marked s later (--lease-timeout-s $lease_s); $others runs of other replicas FINISHED, $lost more of replica $victim INTERRUPTED"
  log "kill: $kill_summary"
fi

# ---- stop: balancer, replicas ---------------------------------------------------------
stop() {  # stop PID NAME LOG: SIGTERM, wait up to 10 s, the exit status must be 0
  kill -TERM "$1"
  stop_wait "$1" "$2" "$3"
}
stop_wait() {  # stop_wait PID NAME LOG: wait up to 10 s for it to end, its status must be 0
  for _ in $(seq 1 100); do kill -0 "$1" 2>/dev/null || break; sleep 0.1; done
  kill -0 "$1" 2>/dev/null && fail "$2 did not stop within 10 s of SIGTERM"
  local rc=0
  wait "$1" || rc=$?
  if [ "$rc" -ne 0 ]; then
    tail -n 20 "$tmp/logs/$3.err" >&2 || true
    fail "$2 exited with $rc on SIGTERM"
  fi
}
for i in $(seq 0 $((replicas - 1))); do
  [ "$((i + 1))" -eq "${victim:-0}" ] && continue  # killed above
  stop "${srv_pids[$i]}" "replica $((i + 1))" "server$((i + 1))"
done
[ -n "${lb_pid:-}" ] && kill -TERM "$lb_pid" 2>/dev/null || true

rate=$(awk -v n="$runs" -v s="$elapsed" 'BEGIN { printf "%.2f", n / s }')
echo "cluster: ---- summary ----"
echo "cluster: store $store, $([ "$direct" -eq 1 ] && echo "no balancer" || echo "haproxy $lb_addr"), $replicas replicas (TLS+tokens, metrics on :$metrics_port)"
echo "cluster: sweep: $runs runs FINISHED in $elapsed s ($rate runs/s, submit and wait included)"
echo "cluster: spread: $spread"
echo "cluster: viewer: $viewer_summary"
echo "cluster: kill: $kill_summary"
echo "cluster: the other replicas exit 0 on SIGTERM"
echo "cluster: PASS"
