-- A job that becomes claimable (submitted, or put back in the queue) is
-- announced on the channel `patchwork_jobs` as its id when its transaction
-- commits: the idle workers of every node wake at once instead of at their
-- next poll.
CREATE FUNCTION patchwork_notify_queued() RETURNS trigger AS $$
BEGIN
    PERFORM pg_notify('patchwork_jobs', NEW.id);
    RETURN NEW;
END
$$ LANGUAGE plpgsql;

CREATE TRIGGER jobs_notify_queued AFTER INSERT OR UPDATE OF status ON jobs
    FOR EACH ROW WHEN (NEW.status = 'queued') EXECUTE FUNCTION patchwork_notify_queued();

-- A job cancelled or deleted through any node is announced on
-- `patchwork_stops` as its id: the node running it stops the run at once
-- (the worker's next lease renewal, within a second, notices it too).
CREATE FUNCTION patchwork_notify_stopped() RETURNS trigger AS $$
BEGIN
    PERFORM pg_notify('patchwork_stops', OLD.id);
    RETURN NULL;
END
$$ LANGUAGE plpgsql;

CREATE TRIGGER jobs_notify_cancelled AFTER UPDATE OF status ON jobs
    FOR EACH ROW WHEN (NEW.status = 'cancelled' AND OLD.status <> 'cancelled')
    EXECUTE FUNCTION patchwork_notify_stopped();

CREATE TRIGGER jobs_notify_deleted AFTER DELETE ON jobs
    FOR EACH ROW EXECUTE FUNCTION patchwork_notify_stopped();
