-- 0004: campaigns. A campaign directory's campaign.db indexes its runs (one
-- run file each) and the knowledge bases made between its steps. The tables
-- exist, empty, in every stepstone file.

-- The campaign itself: one row.
CREATE TABLE campaign (
    id      INTEGER PRIMARY KEY CHECK (id = 1),
    config  TEXT NOT NULL,  -- effective campaign config as JSON, step configs inline
    created TEXT NOT NULL   -- UTC, ISO 8601
);

-- Every run of the campaign, in plan order: source runs, then target runs
-- (treatments x seeds).
CREATE TABLE campaign_run (
    id               INTEGER PRIMARY KEY,  -- plan order
    step             TEXT    NOT NULL CHECK (step IN ('source', 'target')),
    treatment        TEXT    NOT NULL,     -- 'none' for source runs
    seed             INTEGER NOT NULL,
    file             TEXT    NOT NULL UNIQUE,  -- run file, relative to the campaign directory
    generations      INTEGER NOT NULL,     -- generations asked for
    status           TEXT    NOT NULL CHECK (status IN ('pending', 'running', 'finished', 'failed')),
    generations_done INTEGER NOT NULL DEFAULT -1,
    best_reward      REAL,                 -- best task reward of the run so far
    digest           TEXT,                 -- db digest of the finished run file
    wall_time        REAL    NOT NULL DEFAULT 0,  -- seconds spent running it, over every attempt
    error            TEXT                  -- last error line of a failed attempt
);

-- The knowledge bases the campaign made: 'kb' (export of the best source run,
-- merge of all, or a copy of a given file) and 'kb-rand' (its randomized twin).
CREATE TABLE campaign_kb (
    name      TEXT PRIMARY KEY,
    file      TEXT    NOT NULL,  -- relative to the campaign directory
    made_from TEXT    NOT NULL,  -- e.g. 'best source/seed-3.db', 'merge of 30 source runs', 'randomize kb seed 1'
    segments  INTEGER NOT NULL,
    digest    TEXT    NOT NULL   -- content digest (db::kb_digest)
) WITHOUT ROWID;
