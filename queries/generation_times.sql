-- Where a run's time goes: mean seconds per generation in each phase, and the share of each.
-- Parameters: none (every run of the file; generation 0 left out, it evaluates twice as many).
-- Columns: run_id, generations, evaluations_per_s, simulation_s, kb_s, diversity_s, selection_s,
--          database_s, wall_s (means per generation), database_share (database_s / wall_s).
SELECT run_id,
       count(*)                                  AS generations,
       sum(evaluations) / sum(wall_time)         AS evaluations_per_s,
       avg(time_simulation)                      AS simulation_s,
       avg(time_kb)                              AS kb_s,
       avg(time_diversity)                       AS diversity_s,
       avg(time_selection)                       AS selection_s,
       avg(time_database)                        AS database_s,
       avg(wall_time)                            AS wall_s,
       sum(time_database) / sum(wall_time)       AS database_share
FROM generation
WHERE generation > 0
GROUP BY run_id
ORDER BY run_id;
