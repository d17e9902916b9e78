-- the policies a run evaluated up to generation :to, those that collected a
-- ball, and the mean r_max of the policies of generations :from to :to
-- (NULL without a shaping KB)
SELECT count(*),
       coalesce(sum(balls > 0), 0),
       avg(CASE WHEN generation >= :from THEN r_max END)
FROM individual
WHERE run_id = :run_id AND generation <= :to
