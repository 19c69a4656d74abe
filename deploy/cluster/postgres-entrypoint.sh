#!/usr/bin/env bash
# The compose `postgres` service's entrypoint: on first start initialises the cluster in
# /var/lib/postgresql/data with the `mbstream` role (password from the file given as
# $POSTGRES_PASSWORD_FILE) and database, password authentication for the network; then runs
# PostgreSQL in the foreground (SIGTERM: fast shutdown).
set -euo pipefail
bin=$(ls -d /usr/lib/postgresql/*/bin | sort -V | tail -n1)
data=/var/lib/postgresql/data
if [ ! -s "$data/PG_VERSION" ]; then
  "$bin/initdb" -D "$data" -U postgres --auth-local=trust --auth-host=scram-sha-256 -E UTF8 >/dev/null
  echo "host all all 0.0.0.0/0 scram-sha-256" >>"$data/pg_hba.conf"
  "$bin/pg_ctl" -D "$data" -w -s -o "-c listen_addresses=''" start
  psql -U postgres -q -v ON_ERROR_STOP=1 \
    -c "CREATE ROLE mbstream LOGIN PASSWORD '$(head -n1 "$POSTGRES_PASSWORD_FILE")'" \
    -c "CREATE DATABASE mbstream OWNER mbstream"
  "$bin/pg_ctl" -D "$data" -w -s -m fast stop
fi
exec "$bin/postgres" -D "$data" -c listen_addresses='*' -c max_connections=200
