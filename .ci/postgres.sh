# Sourced by .ci/run: starts a throwaway PostgreSQL cluster for the service
# tests (an unprivileged user, a free port on 127.0.0.1, trust
# authentication, a temporary data folder), exports its URL as
# PATCHWORK_TEST_POSTGRES, and stops and removes it when the run exits.

pg_bin=$(ls -d /usr/lib/postgresql/*/bin 2>/dev/null | sort -V | tail -n 1)
if [ -z "$pg_bin" ]; then
    echo "PostgreSQL's server programs are missing (Debian package postgresql)" >&2
    exit 1
fi
pg_dir=$(mktemp -d /tmp/patchwork-pg.XXXXXX)
pg_port=$(python3 -c 'import socket; s = socket.socket(); s.bind(("127.0.0.1", 0)); print(s.getsockname()[1])')
# initdb and postgres refuse to run as root: run them as the postgres user
# the Debian package creates.
as_owner=()
if [ "$(id -u)" -eq 0 ]; then
    chown postgres "$pg_dir"
    as_owner=(runuser -u postgres --)
fi
"${as_owner[@]}" "$pg_bin/initdb" -D "$pg_dir/data" -U patchwork --auth=trust -E UTF8 >/dev/null
"${as_owner[@]}" "$pg_bin/pg_ctl" -D "$pg_dir/data" -l "$pg_dir/log" -w \
    -o "-p $pg_port -k $pg_dir -c listen_addresses=127.0.0.1 -c max_connections=400 -c fsync=off" start >/dev/null
stop_postgres() {
    "${as_owner[@]}" "$pg_bin/pg_ctl" -D "$pg_dir/data" -m immediate stop >/dev/null 2>&1 || true
    rm -rf "$pg_dir"
}
trap stop_postgres EXIT
export PATCHWORK_TEST_POSTGRES="postgres://patchwork@127.0.0.1:$pg_port/postgres"
