-- 0002: evolution runs, their generations, evaluated individuals, stored
-- genomes and the checkpoint a run resumes from.

-- One evolution run. A run file usually holds one run.
CREATE TABLE run (
    id               INTEGER PRIMARY KEY,
    task             TEXT    NOT NULL CHECK (task IN ('source', 'target')),
    treatment        TEXT    NOT NULL DEFAULT 'none',
    seed             INTEGER NOT NULL,
    config           TEXT    NOT NULL,          -- effective config as JSON, seed included
    status           TEXT    NOT NULL CHECK (status IN ('running', 'finished')),
    generations      INTEGER NOT NULL,          -- generations asked for (0 = random start only)
    generations_done INTEGER NOT NULL DEFAULT -1, -- last committed generation, -1 before any
    evaluations      INTEGER NOT NULL DEFAULT 0,
    nan_outputs      INTEGER NOT NULL DEFAULT 0, -- network outputs that were NaN (replaced by 0)
    program_version  TEXT    NOT NULL,
    created          TEXT    NOT NULL            -- UTC, ISO 8601
);

-- Statistics of one generation, written in the generation's transaction.
CREATE TABLE generation (
    run_id        INTEGER NOT NULL REFERENCES run (id) ON DELETE CASCADE,
    generation    INTEGER NOT NULL,
    best_reward   REAL    NOT NULL,  -- best task reward among the survivors
    mean_reward   REAL    NOT NULL,
    median_reward REAL    NOT NULL,
    front_sizes   TEXT    NOT NULL,  -- JSON array: size of each non-dominated front of the mixed population
    diversity_min REAL    NOT NULL,
    diversity_max REAL    NOT NULL,
    evaluations   INTEGER NOT NULL,  -- evaluations run in this generation
    wall_time     REAL    NOT NULL,  -- seconds, the whole generation (timings are not part of the digest)
    time_simulation REAL  NOT NULL,  -- seconds evaluating (simulation and networks)
    time_kb       REAL    NOT NULL,  -- seconds observing into the knowledge base
    time_diversity REAL   NOT NULL,  -- seconds computing the diversity objective
    time_selection REAL   NOT NULL,  -- seconds in sorting, crowding and selection
    time_database REAL    NOT NULL,  -- seconds writing this generation (before the commit)
    PRIMARY KEY (run_id, generation)
) WITHOUT ROWID;

-- Every evaluated individual. `id` is unique within the run and never reused.
CREATE TABLE individual (
    run_id     INTEGER NOT NULL REFERENCES run (id) ON DELETE CASCADE,
    id         INTEGER NOT NULL,
    generation INTEGER NOT NULL,    -- generation in which it was evaluated
    parent_id  INTEGER,             -- NULL for the random individuals of generation 0
    reward     REAL    NOT NULL,    -- task reward (balls / 24)
    fitness    REAL    NOT NULL,    -- first objective (reward, or reward + shaping for `sum`)
    diversity  REAL    NOT NULL,    -- diversity objective when it was evaluated
    shaping    REAL,                -- r_max from the knowledge base, NULL without one
    balls      INTEGER NOT NULL,
    steps      INTEGER NOT NULL,    -- simulation steps run (fewer when the robot stood still)
    PRIMARY KEY (run_id, id)
) WITHOUT ROWID;
CREATE INDEX individual_by_generation ON individual (run_id, generation);

-- Genomes kept for replay: the first front and the best of every generation
-- (all with --retain all). JSON, readable with SQL's json functions.
CREATE TABLE genome (
    run_id        INTEGER NOT NULL REFERENCES run (id) ON DELETE CASCADE,
    individual_id INTEGER NOT NULL,
    genome        TEXT    NOT NULL,
    PRIMARY KEY (run_id, individual_id)
) WITHOUT ROWID;

-- The population a run resumes from: replaced in every generation's transaction.
CREATE TABLE checkpoint (
    run_id     INTEGER PRIMARY KEY REFERENCES run (id) ON DELETE CASCADE,
    generation INTEGER NOT NULL,
    state      TEXT    NOT NULL      -- JSON: counters, survivors (id, genome, objectives, cells)
);
