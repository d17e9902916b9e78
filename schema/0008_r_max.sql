-- 0008: one name for a policy's knowledge-base score. The column that schema 2
-- called `shaping` is r_max, the largest average reward of the KB segments the
-- policy's segments match (0 when none match), the name the JSON, CSV and docs
-- already used. Values are untouched, so every digest stays. A file of an older
-- schema opened read-only shows the column under both names (db/database.cpp).
ALTER TABLE individual RENAME COLUMN shaping TO r_max;
