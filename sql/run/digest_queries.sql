-- The scientific content of a run file, hashed by `stepstone db digest`.
-- One query per statement, each with a total order; no timings, dates or versions.
-- the shaping KB's file path is left out: its content digest (transfer.kb_digest) stays in
SELECT task, treatment, seed, json_remove(config, '$.transfer.kb'), status, generations, generations_done, evaluations, nan_outputs
FROM run ORDER BY id;
SELECT run_id, generation, best_reward, mean_reward, median_reward, front_sizes, diversity_min,
       diversity_max, evaluations
FROM generation ORDER BY run_id, generation;
SELECT run_id, id, generation, parent_id, reward, fitness, diversity, shaping, balls, steps,
       presses, pickups, carry_steps, basket_releases
FROM individual ORDER BY run_id, id;
SELECT run_id, individual_id, genome FROM genome ORDER BY run_id, individual_id;
SELECT run_id, generation, state FROM checkpoint ORDER BY run_id
;
SELECT name, segment_width, channels, delta, match, randomized_seed FROM kb ORDER BY id;
SELECT kb_id, source, run, first_generation, last_generation, policies FROM kb_source ORDER BY kb_id, source;
SELECT kb_id, id, cum_reward, count, first_source, first_generation, last_source, last_generation, segment_values
FROM kb_segment ORDER BY kb_id, id;
SELECT run_id, individual_id, kb_id, segment, kb_segment_id, distance, average_reward
FROM policy_segment ORDER BY run_id, individual_id, kb_id, segment
