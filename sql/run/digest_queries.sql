-- The scientific content of a run file, hashed by `stepstone db digest`.
-- One query per statement, each with a total order; no timings, dates or versions.
SELECT task, treatment, seed, config, status, generations, generations_done, evaluations, nan_outputs
FROM run ORDER BY id;
SELECT run_id, generation, best_reward, mean_reward, median_reward, front_sizes, diversity_min,
       diversity_max, evaluations
FROM generation ORDER BY run_id, generation;
SELECT run_id, id, generation, parent_id, reward, fitness, diversity, shaping, balls, steps
FROM individual ORDER BY run_id, id;
SELECT run_id, individual_id, genome FROM genome ORDER BY run_id, individual_id;
SELECT run_id, generation, state FROM checkpoint ORDER BY run_id
