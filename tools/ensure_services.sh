#!/usr/bin/env bash
# Make sure the services the tests need are reachable:
#   Redis       127.0.0.1:6379
#   PostgreSQL  127.0.0.1:5432, database "test", user postgres, trust authentication
# Starts them with this machine's commands if they are down, installs them with apt-get if they
# are missing, creates the "test" database and trust authentication, and exits non-zero if a
# service is still unreachable. Called by .ci/run before the tests.
set -uo pipefail

log() { printf 'ensure_services: %s\n' "$*" >&2; }

as_root() {
    if [ "$(id -u)" -eq 0 ]; then "$@"; elif command -v sudo >/dev/null; then sudo -n "$@"; else "$@"; fi
}

port_open() {  # port_open PORT: true if something listens on 127.0.0.1:PORT
    timeout 2 bash -c "exec 3<>/dev/tcp/127.0.0.1/$1" 2>/dev/null
}

wait_port() {  # wait_port PORT SECONDS
    local i
    for ((i = 0; i < $2; i++)); do
        port_open "$1" && return 0
        sleep 1
    done
    return 1
}

redis_ok() { command -v redis-cli >/dev/null && [ "$(redis-cli -h 127.0.0.1 -p 6379 ping 2>/dev/null)" = "PONG" ]; }
pg_ok() { command -v psql >/dev/null && psql -h 127.0.0.1 -p 5432 -U postgres -d test -tAc 'SELECT 1' >/dev/null 2>&1; }

install_packages() {
    log "installing redis-server and postgresql with apt-get"
    export DEBIAN_FRONTEND=noninteractive
    as_root apt-get update && as_root apt-get install -y redis-server postgresql
}

start_redis() {
    log "starting Redis"
    as_root mkdir -p /var/lib/redis /var/log/redis
    as_root redis-server --daemonize yes --bind 127.0.0.1 -::1 --port 6379 --save "" \
        --appendonly no --dir /var/lib/redis --logfile /var/log/redis/ci.log
    wait_port 6379 20
}

pg_version() { ls /etc/postgresql 2>/dev/null | sort -V | tail -n 1; }

pg_trust() {  # trust authentication for local and loopback connections, then reload
    local hba
    hba="/etc/postgresql/$(pg_version)/main/pg_hba.conf"
    [ -f "$hba" ] || return 0
    if grep -Eq '^(local|host)\s.*\s(peer|md5|scram-sha-256)\s*$' "$hba"; then
        log "setting trust authentication in $hba"
        as_root sed -i -E 's/^((local|host)\s.*\s)(peer|md5|scram-sha-256)\s*$/\1trust/' "$hba"
        as_root pg_ctlcluster --skip-systemctl-redirect "$(pg_version)" main reload || true
    fi
}

start_postgres() {
    log "starting PostgreSQL $(pg_version)"
    as_root pg_ctlcluster --skip-systemctl-redirect "$(pg_version)" main start
    wait_port 5432 30
}

pg_test_db() {  # create the "test" database if it is missing
    if ! psql -h 127.0.0.1 -U postgres -d postgres -tAc \
            "SELECT 1 FROM pg_database WHERE datname = 'test'" 2>/dev/null | grep -q 1; then
        log "creating database test"
        psql -h 127.0.0.1 -U postgres -d postgres -c 'CREATE DATABASE test' >/dev/null
    fi
}

if ! command -v redis-server >/dev/null || ! command -v pg_ctlcluster >/dev/null \
        || [ -z "$(pg_version)" ]; then
    install_packages || log "apt-get failed"
fi

redis_ok || { port_open 6379 || start_redis; } || log "Redis did not start"
if ! pg_ok; then
    port_open 5432 || start_postgres || log "PostgreSQL did not start"
    pg_trust
    pg_test_db
fi

status=0
if redis_ok; then log "Redis OK (127.0.0.1:6379)"; else log "Redis is NOT reachable on 127.0.0.1:6379"; status=1; fi
if pg_ok; then log "PostgreSQL OK (127.0.0.1:5432, database test)"; else
    log "PostgreSQL is NOT reachable on 127.0.0.1:5432 (database test, user postgres)"; status=1; fi
exit $status
