-- Balloon profiles: a lab's named balloons (the balloon and the patch as a
-- design takes them, typically from a calibration), per API key. A job
-- request naming one gets the profile's materials written into its spec at
-- submission, so a job never depends on a profile that changes later.
CREATE TABLE balloon_profiles (
    owner       TEXT NOT NULL,              -- SHA-256 of the API key; '' when keys are off
    name        TEXT NOT NULL,
    profile     TEXT NOT NULL,              -- {"balloon": …, "patch": …}, as JSON
    source_job  TEXT,                       -- the calibration job that saved it
    created_at  TEXT NOT NULL,
    updated_at  TEXT NOT NULL,
    PRIMARY KEY (owner, name)
);
