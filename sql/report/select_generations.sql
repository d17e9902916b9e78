-- A run's statistics per generation, for its reward figure, with the mean and
-- largest r_max of the policies evaluated in that generation (NULL without a
-- knowledge base).
SELECT g.generation, g.best_reward, g.median_reward, g.mean_reward,
       (SELECT avg(i.shaping) FROM individual AS i
        WHERE i.run_id = g.run_id AND i.generation = g.generation) AS mean_shaping,
       (SELECT max(i.shaping) FROM individual AS i
        WHERE i.run_id = g.run_id AND i.generation = g.generation) AS max_shaping
FROM generation AS g
WHERE g.run_id = :run_id
ORDER BY g.generation;
