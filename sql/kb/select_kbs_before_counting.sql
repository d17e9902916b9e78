-- select_kbs.sql on a file of schema 4 to 6 (opened read-only, not migrated): every KB
-- made before schema 7 counts by occurrence
SELECT id, name, segment_width, channels, delta, match, 'occurrence' AS counting, randomized_seed FROM kb ORDER BY id
