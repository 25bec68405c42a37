#!/bin/bash
# Entry point of the Debian-based PostgreSQL image, as the official image's for the variables
# flexride uses: on an empty PGDATA, initdb with POSTGRES_USER (default postgres) and
# POSTGRES_PASSWORD or POSTGRES_PASSWORD_FILE, password (scram-sha-256) authentication from
# any address, and the database POSTGRES_DB (default: the user's name). The server of that
# set-up listens on a private socket only, so pg_isready (the health check) says "ready" only
# for the real server.
set -euo pipefail

file_env() {  # file_env VAR: VAR from VAR_FILE when that is set (not both)
    local var=$1 file_var="${1}_FILE"
    if [ -n "${!var:-}" ] && [ -n "${!file_var:-}" ]; then
        echo "postgres-entrypoint: set $var or $file_var, not both" >&2
        exit 1
    fi
    if [ -n "${!file_var:-}" ]; then
        export "$var"="$(< "${!file_var}")"
    fi
    unset "$file_var"
}

init_cluster() {
    local user=${POSTGRES_USER:-postgres} db pwfile sock
    db=${POSTGRES_DB:-$user}
    if [ -z "${POSTGRES_PASSWORD:-}" ]; then
        echo "postgres-entrypoint: set POSTGRES_PASSWORD or POSTGRES_PASSWORD_FILE" >&2
        exit 1
    fi
    pwfile=$(mktemp)
    printf '%s' "$POSTGRES_PASSWORD" > "$pwfile"
    initdb -D "$PGDATA" --username="$user" --pwfile="$pwfile" --encoding=UTF8 --no-locale \
        --auth-local=trust --auth-host=scram-sha-256 >/dev/null
    rm -f "$pwfile"
    echo "host all all all scram-sha-256" >> "$PGDATA/pg_hba.conf"
    echo "listen_addresses = '*'" >> "$PGDATA/postgresql.conf"
    if [ "$db" != postgres ]; then
        sock=$(mktemp -d)
        pg_ctl -D "$PGDATA" -o "-c listen_addresses='' -k $sock" -w start >/dev/null
        psql -v ON_ERROR_STOP=1 -h "$sock" -U "$user" -d postgres -q \
            -c "CREATE DATABASE \"$db\""
        pg_ctl -D "$PGDATA" -m fast -w stop >/dev/null
        rmdir "$sock"
    fi
    echo "postgres-entrypoint: initialised $PGDATA (user $user, database $db)" >&2
}

file_env POSTGRES_PASSWORD
file_env POSTGRES_USER
file_env POSTGRES_DB
if [ "${1:0:1}" = - ]; then
    set -- postgres "$@"
fi
if [ "$1" = postgres ] && [ ! -s "$PGDATA/PG_VERSION" ]; then
    init_cluster
fi
exec "$@"
