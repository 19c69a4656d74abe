#!/usr/bin/env bash
# Makes the throwaway TLS material and access tokens that the docker-compose demo and the
# multi-host test use. Never commit what it writes (deploy/secrets/ is git-ignored).
#
#   deploy/make-secrets.sh [OUT_DIR] [--san SAN] [--web-san SAN] [--force]
#
#   OUT_DIR   default deploy/secrets (beside this script)
#   --san     subjectAltName of the server certificate, openssl syntax; default
#             "DNS:server,DNS:localhost,IP:127.0.0.1" (`server` is the compose service)
#   --web-san subjectAltName of the viewer's web certificate (--web-tls); default
#             "DNS:localhost,IP:127.0.0.1" (the compose demo publishes it on the host's loopback)
#   --force   overwrite existing files
#
# Writes:
#   ca.pem             CA certificate that clients and viewers trust (--ca); its key is
#                      deleted once the server certificate is signed
#   server.pem         server certificate (--tls-cert), signed by ca.pem, SAN as given
#   server.key         its private key (--tls-key)
#   tokens             server token file (--token-file): `<token> <role>[,<role>]` lines
#   client.token       token of the client: roles submit,run,view (--token-file of the CLI)
#   viewer.token       token of the viewer: role view (--token-file of the viewer)
#   web.pem, web.key   the viewer's web certificate and key (--web-tls), signed by ca.pem
set -euo pipefail

here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
out="$here/secrets"
san="DNS:server,DNS:localhost,IP:127.0.0.1"
web_san="DNS:localhost,IP:127.0.0.1"
force=0
while [ $# -gt 0 ]; do
  case "$1" in
    --san) san="$2"; shift 2 ;;
    --web-san) web_san="$2"; shift 2 ;;
    --force) force=1; shift ;;
    -h|--help) sed -n '2,24p' "$0" | sed 's/^# \{0,1\}//'; exit 0 ;;
    -*) echo "make-secrets: unknown option $1 (see --help)" >&2; exit 2 ;;
    *) out="$1"; shift ;;
  esac
done

command -v openssl >/dev/null || { echo "make-secrets: openssl not found (scripts/setup.sh installs it)" >&2; exit 2; }
if [ -e "$out/server.key" ] && [ "$force" -eq 0 ]; then
  echo "make-secrets: $out already holds secrets; pass --force to replace them" >&2
  exit 0
fi

umask 077
mkdir -p "$out"
chmod 700 "$out"
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

openssl req -x509 -newkey rsa:2048 -nodes -days 30 -subj /CN=mbstream-demo-ca \
  -keyout "$work/ca.key" -out "$out/ca.pem" 2>/dev/null
openssl req -newkey rsa:2048 -nodes -subj /CN=mbstream-server \
  -keyout "$out/server.key" -out "$work/server.csr" 2>/dev/null
printf 'subjectAltName=%s\nextendedKeyUsage=serverAuth\n' "$san" > "$work/ext"
openssl x509 -req -in "$work/server.csr" -CA "$out/ca.pem" -CAkey "$work/ca.key" \
  -CAcreateserial -CAserial "$work/ca.srl" -days 30 -extfile "$work/ext" \
  -out "$out/server.pem" 2>/dev/null
openssl req -newkey rsa:2048 -nodes -subj /CN=mbstream-viewer-web \
  -keyout "$out/web.key" -out "$work/web.csr" 2>/dev/null
printf 'subjectAltName=%s\nextendedKeyUsage=serverAuth\n' "$web_san" > "$work/web-ext"
openssl x509 -req -in "$work/web.csr" -CA "$out/ca.pem" -CAkey "$work/ca.key" \
  -CAserial "$work/ca.srl" -days 30 -extfile "$work/web-ext" -out "$out/web.pem" 2>/dev/null

client_token=$(openssl rand -hex 32)
viewer_token=$(openssl rand -hex 32)
printf '%s submit,run,view\n%s view\n' "$client_token" "$viewer_token" > "$out/tokens"
printf '%s\n' "$client_token" > "$out/client.token"
printf '%s\n' "$viewer_token" > "$out/viewer.token"

# The directory stays owner-only; the files are world-readable inside it so that the
# containers' unprivileged user can read them from the compose secrets bind mounts.
chmod 644 "$out"/ca.pem "$out"/server.pem "$out"/server.key "$out"/tokens "$out"/*.token \
  "$out"/web.pem "$out"/web.key
echo "make-secrets: wrote ca.pem server.pem server.key tokens client.token viewer.token web.pem web.key to $out (SAN $san, web SAN $web_san)"
