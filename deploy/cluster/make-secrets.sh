#!/usr/bin/env bash
# The cluster's throwaway secrets: what deploy/make-secrets.sh makes (CA, server certificate
# and key, tokens), with a certificate valid for the balancer and every replica, plus the
# PostgreSQL password and HAProxy's certificate-and-key file. Never commit them
# (deploy/cluster/secrets/ is git-ignored).
#
#   deploy/cluster/make-secrets.sh [OUT_DIR] [--san SAN] [--force]
#
#   OUT_DIR   default deploy/cluster/secrets
#   --san     the certificate's subjectAltName; default the compose names:
#             DNS:lb,DNS:server1,DNS:server2,DNS:server3,DNS:localhost,IP:127.0.0.1
#
# Writes, besides deploy/make-secrets.sh's files: pg.password (the `mbstream` database role's
# password, one line) and haproxy.pem (server.pem then server.key, as HAProxy's `crt` reads).
set -euo pipefail

here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
out=$here/secrets
san="DNS:lb,DNS:server1,DNS:server2,DNS:server3,DNS:localhost,IP:127.0.0.1"
force=()
while [ $# -gt 0 ]; do
  case "$1" in
    --san) san=$2; shift 2 ;;
    --force) force=(--force); shift ;;
    -h|--help) sed -n '2,15p' "$0" | sed 's/^# \{0,1\}//'; exit 0 ;;
    -*) echo "make-secrets: unknown option $1 (see --help)" >&2; exit 2 ;;
    *) out=$1; shift ;;
  esac
done
"$here/../make-secrets.sh" "$out" --san "$san" "${force[@]}" >/dev/null
umask 077
[ -s "$out/pg.password" ] && [ ${#force[@]} -eq 0 ] || openssl rand -hex 16 >"$out/pg.password"
cat "$out/server.pem" "$out/server.key" >"$out/haproxy.pem"
# Compose hands secrets to containers as files owned by the host's user: keep them readable
# by the containers' own users (postgres, haproxy, mbstream), as the demo's are.
chmod 644 "$out/pg.password" "$out/haproxy.pem"
echo "make-secrets: wrote the cluster's secrets to $out (SAN $san)"
