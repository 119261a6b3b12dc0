-- Leases. A running job is held by one worker until `lease_until`, which the
-- worker renews while it runs; a job whose lease ran out (its node died) is
-- claimed again. `attempt` counts the claims and fences the writes of a
-- worker that lost its lease; `checkpoint_evaluations` keeps a checkpoint
-- from being replaced by an older one; `node` names the holder, and
-- `taken_over` says whether its claim took the job from a lapsed lease.
ALTER TABLE jobs ADD COLUMN attempt INTEGER NOT NULL DEFAULT 0;
ALTER TABLE jobs ADD COLUMN lease_until TEXT;
ALTER TABLE jobs ADD COLUMN node TEXT;
ALTER TABLE jobs ADD COLUMN checkpoint_evaluations INTEGER NOT NULL DEFAULT 0;
ALTER TABLE jobs ADD COLUMN taken_over BOOLEAN NOT NULL DEFAULT FALSE;
