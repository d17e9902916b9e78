-- The scientific content of a run file, hashed by `stepstone db digest`.
-- One query per statement, each with a total order; no timings, dates or versions.
-- the shaping KB's and the seed source's file paths are left out: their content digests
-- (transfer.kb_digest, transfer.seed.digest) stay in
SELECT task, treatment, seed, json_remove(config, '$.transfer.kb', '$.transfer.seed.from'), status, generations, generations_done, evaluations, nan_outputs
FROM run ORDER BY id;
SELECT run_id, generation, best_reward, mean_reward, median_reward, front_sizes, diversity_min,
       diversity_max, evaluations
FROM generation ORDER BY run_id, generation;
SELECT run_id, id, generation, parent_id, reward, fitness, diversity, r_max, balls, steps,
       presses, pickups, carry_steps, basket_releases
FROM individual ORDER BY run_id, id;
SELECT run_id, individual_id, genome FROM genome ORDER BY run_id, individual_id;
SELECT run_id, generation, state FROM checkpoint ORDER BY run_id
;
SELECT name, segment_width, channels, delta, match, randomized_seed FROM kb ORDER BY id;
SELECT kb_id, source, run, first_generation, last_generation, policies FROM kb_source ORDER BY kb_id, source;
-- segment values as float32 whatever their stored form (raw or packed, docs/schema.md)
SELECT s.kb_id, s.id, s.cum_reward, s.count, s.first_source, s.first_generation, s.last_source, s.last_generation,
       segment_floats(s.segment_values, k.segment_width, k.channels)
FROM kb_segment AS s JOIN kb AS k ON k.id = s.kb_id ORDER BY s.kb_id, s.id;
SELECT run_id, individual_id, kb_id, segment, kb_segment_id, distance, average_reward
FROM policy_segment ORDER BY run_id, individual_id, kb_id, segment
