#!/usr/bin/env bash
# Makes the Secret `mbstream` the manifests mount at /run/secrets, from the files
# deploy/cluster/make-secrets.sh writes, one key per compose secret (same names):
#
#   deploy/cluster/make-secrets.sh --san DNS:mbstream,DNS:localhost,IP:127.0.0.1
#   deploy/k8s/create-secret.sh [SECRETS_DIR]   (default deploy/cluster/secrets)
#   kubectl apply -f deploy/k8s/postgres.yaml -f deploy/k8s/server.yaml -f deploy/k8s/viewer.yaml
#   kubectl apply -f deploy/k8s/client-job.yaml
set -euo pipefail
here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
dir=${1:-$here/../cluster/secrets}
kubectl create secret generic mbstream \
  --from-file=ca="$dir/ca.pem" \
  --from-file=server_cert="$dir/server.pem" \
  --from-file=server_key="$dir/server.key" \
  --from-file=tokens="$dir/tokens" \
  --from-file=client_token="$dir/client.token" \
  --from-file=viewer_token="$dir/viewer.token" \
  --from-file=pg_password="$dir/pg.password"
