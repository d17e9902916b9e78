-- 0003: knowledge bases (the paper's behaviour segments with their rewards),
-- their provenance, and which KB segment each segment of a stored policy matched.

-- One knowledge base. A run file holds the KB its run builds (name 'run');
-- a KB file (kb export / merge / randomize) holds one KB.
CREATE TABLE kb (
    id              INTEGER PRIMARY KEY,
    name            TEXT    NOT NULL UNIQUE,
    segment_width   INTEGER NOT NULL CHECK (segment_width >= 1),  -- time steps per segment
    channels        INTEGER NOT NULL CHECK (channels >= 1),       -- values per time step
    delta           REAL    NOT NULL CHECK (delta > 0),           -- Euclidean threshold (dist < delta matches)
    match           TEXT    NOT NULL CHECK (match IN ('within_delta', 'nearest')),
    randomized_seed INTEGER,                                      -- set by kb randomize: rewards are U[0, 1) draws
    created         TEXT    NOT NULL                              -- UTC, ISO 8601
);

-- The runs that fed a KB (its provenance), in the order they were added.
CREATE TABLE kb_source (
    kb_id            INTEGER NOT NULL REFERENCES kb (id) ON DELETE CASCADE,
    source           INTEGER NOT NULL,  -- index used by kb_segment.first_source / last_source
    run              TEXT    NOT NULL,  -- run name, unique within the KB
    first_generation INTEGER NOT NULL,
    last_generation  INTEGER NOT NULL,
    policies         INTEGER NOT NULL,  -- policies observed from it
    PRIMARY KEY (kb_id, source)
);

-- The segments of a KB. average_reward is the paper's saliency.
CREATE TABLE kb_segment (
    kb_id            INTEGER NOT NULL REFERENCES kb (id) ON DELETE CASCADE,
    id               INTEGER NOT NULL,  -- segment id within the KB, from 0, in insertion order
    cum_reward       REAL    NOT NULL,
    count            INTEGER NOT NULL CHECK (count >= 1),
    average_reward   REAL    GENERATED ALWAYS AS (cum_reward / count) VIRTUAL,
    first_source     INTEGER NOT NULL,  -- the observation that inserted it
    first_generation INTEGER NOT NULL,
    last_source      INTEGER NOT NULL,  -- the latest observation credited to it
    last_generation  INTEGER NOT NULL,
    segment_values   BLOB    NOT NULL,  -- float32 little endian, segment_width rows x channels, row-major
    PRIMARY KEY (kb_id, id)
);

-- For saliency queries: the KB match of every segment of a stored policy
-- (filled by kb annotate).
CREATE TABLE policy_segment (
    run_id         INTEGER NOT NULL,
    individual_id  INTEGER NOT NULL,
    kb_id          INTEGER NOT NULL,
    segment        INTEGER NOT NULL,  -- index of the segment in the policy's behaviour (time = segment x width)
    kb_segment_id  INTEGER,           -- NULL when no KB segment lies within delta
    distance       REAL    NOT NULL,
    average_reward REAL    NOT NULL,  -- 0 when unmatched
    PRIMARY KEY (run_id, individual_id, kb_id, segment)
);
