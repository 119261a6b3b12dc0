-- The job spec: the validated job (target in mm, settings, tuning overrides)
-- as the worker runs it, versioned JSON written once at submission
-- (src/service/spec.rs). `request` stays, as the client sent it, for the
-- job's detail and idempotent replays. Jobs stored before this column get
-- their spec from their request at the next start (src/service/upgrade.rs).
ALTER TABLE jobs ADD COLUMN spec TEXT;
