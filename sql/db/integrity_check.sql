-- SQLite's own check of the whole file, stopping at its first problem:
-- one row, 'ok' or a description of what is wrong
PRAGMA integrity_check(1);
