# Sourced by .ci/run: starts a throwaway PostgreSQL cluster for the service
# tests (.ci/pg-cluster: an unprivileged user, a free port on 127.0.0.1,
# trust authentication, a temporary data folder), exports its URL as
# PATCHWORK_TEST_POSTGRES, and removes it when the run exits. Tests that
# restart a database make clusters of their own with the script named by
# PATCHWORK_TEST_PG_CLUSTER.

export PATCHWORK_TEST_PG_CLUSTER="$PWD/.ci/pg-cluster"
pg_dir=$(mktemp -u /tmp/patchwork-pg.XXXXXX)
trap '"$PATCHWORK_TEST_PG_CLUSTER" remove "$pg_dir"' EXIT
PATCHWORK_TEST_POSTGRES=$("$PATCHWORK_TEST_PG_CLUSTER" init "$pg_dir")
export PATCHWORK_TEST_POSTGRES
