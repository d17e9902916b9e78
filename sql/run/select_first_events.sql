-- the first generation up to :to in which any evaluated policy of the run
-- pressed the switch, picked a ball up, released one within the basket
-- radius and collected one (NULL when none did), then how many individuals
-- hold milestones and how many there are (older files: NULL columns)
SELECT min(CASE WHEN presses > 0 THEN generation END),
       min(CASE WHEN pickups > 0 THEN generation END),
       min(CASE WHEN basket_releases > 0 THEN generation END),
       min(CASE WHEN balls > 0 THEN generation END),
       count(presses),
       count(*)
FROM individual
WHERE run_id = :run_id AND generation <= :to
