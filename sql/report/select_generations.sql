-- A run's statistics per generation, for its reward figure, with the mean and
-- largest r_max of the policies evaluated in that generation (NULL without a
-- knowledge base). The individuals are grouped once (a correlated subquery
-- per generation would rescan the run's individuals for every generation).
SELECT g.generation, g.best_reward, g.median_reward, g.mean_reward, s.mean_shaping, s.max_shaping
FROM generation AS g
LEFT JOIN (SELECT generation, avg(shaping) AS mean_shaping, max(shaping) AS max_shaping
           FROM individual
           WHERE run_id = :run_id
           GROUP BY generation) AS s ON s.generation = g.generation
WHERE g.run_id = :run_id
ORDER BY g.generation;
