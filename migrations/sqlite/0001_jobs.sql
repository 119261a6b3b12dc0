-- Design jobs and everything they produce. Timestamps are RFC 3339 UTC text.

CREATE TABLE jobs (
    id               TEXT PRIMARY KEY,          -- UUIDv7
    owner            TEXT NOT NULL,             -- SHA-256 of the API key; '' when keys are off
    status           TEXT NOT NULL CHECK (status IN ('queued', 'running', 'succeeded', 'failed', 'cancelled')),
    request          TEXT NOT NULL,             -- the job request, as JSON
    idempotency_key  TEXT,
    created_at       TEXT NOT NULL,
    updated_at       TEXT NOT NULL,
    progress         TEXT,                      -- latest progress, as JSON
    error            TEXT,
    checkpoint       TEXT,                      -- latest DesignCheckpoint, as JSON
    result           TEXT                       -- design.json
);

CREATE UNIQUE INDEX jobs_idempotency ON jobs (owner, idempotency_key)
    WHERE idempotency_key IS NOT NULL;
CREATE INDEX jobs_by_status ON jobs (status, created_at);
CREATE INDEX jobs_by_owner ON jobs (owner, created_at);

-- Server-sent events, kept so a client reconnecting with Last-Event-ID gets
-- what it missed. `seq` is the event id, monotonic per job.
CREATE TABLE events (
    job_id      TEXT NOT NULL REFERENCES jobs (id) ON DELETE CASCADE,
    seq         INTEGER NOT NULL,
    kind        TEXT NOT NULL,
    data        TEXT NOT NULL,
    created_at  TEXT NOT NULL,
    PRIMARY KEY (job_id, seq)
);

-- One row per CMA-ES generation.
CREATE TABLE iterations (
    job_id          TEXT NOT NULL REFERENCES jobs (id) ON DELETE CASCADE,
    evaluations     INTEGER NOT NULL,
    generation      INTEGER NOT NULL,
    best_objective  REAL NOT NULL,
    sigma           REAL NOT NULL,
    elapsed_s       REAL NOT NULL,
    PRIMARY KEY (job_id, evaluations)
);

-- Result files (DXF, SVG, CSV, JSON).
CREATE TABLE files (
    job_id        TEXT NOT NULL REFERENCES jobs (id) ON DELETE CASCADE,
    name          TEXT NOT NULL,
    content_type  TEXT NOT NULL,
    body          BLOB NOT NULL,
    PRIMARY KEY (job_id, name)
);
