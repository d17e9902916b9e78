-- A run's statistics per generation, for its reward figure, with the mean and
-- largest r_max of the policies evaluated in that generation (NULL without a
-- knowledge base). The individuals are grouped once (a correlated subquery
-- per generation would rescan the run's individuals for every generation).
SELECT g.generation, g.best_reward, g.median_reward, g.mean_reward, s.mean_r_max, s.max_r_max
FROM generation AS g
LEFT JOIN (SELECT generation, avg(r_max) AS mean_r_max, max(r_max) AS max_r_max
           FROM individual
           WHERE run_id = :run_id
           GROUP BY generation) AS s ON s.generation = g.generation
WHERE g.run_id = :run_id
ORDER BY g.generation;
