-- 0001: the meta table every stepstone database has.
-- Key/value facts about the file itself: which program created it and when.
CREATE TABLE meta (
    key   TEXT PRIMARY KEY,
    value TEXT NOT NULL
) WITHOUT ROWID;
