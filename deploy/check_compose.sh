#!/usr/bin/env bash
# Validates deploy/docker-compose.yml with Debian's docker-compose (`config -q`: schema,
# interpolation, references; no Docker engine needed). Exits 77 (skipped) when
# docker-compose is not installed (scripts/setup.sh installs it).
set -euo pipefail
here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
if ! command -v docker-compose >/dev/null; then
  echo "check_compose: SKIPPED: docker-compose is not installed (scripts/setup.sh installs it)"
  exit 77
fi
# The build context is staged (deploy/stage.sh) only before a build: an empty stand-in here.
context=$(mktemp -d)
trap 'rm -rf "$context"' EXIT
export MBSTREAM_DEMO_STAGE=$context
docker-compose -f "$here/docker-compose.yml" config -q
services=$(docker-compose -f "$here/docker-compose.yml" config --services | tr '\n' ' ')
echo "check_compose: OK: deploy/docker-compose.yml is valid ($(docker-compose version --short)); services: $services"
