-- What a run's generations cost beside simulation and KB lookups, and how many
-- evaluations its file holds (campaign --dry-run's timing probe).
-- Columns: other_s (mean seconds a generation after generation 0), evaluations.
SELECT (SELECT avg(wall_time - time_simulation - time_kb) FROM generation WHERE generation > 0) AS other_s,
       (SELECT sum(evaluations) FROM generation) AS evaluations;
