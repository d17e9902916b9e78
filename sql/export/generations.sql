-- stepstone export --what generations: one row per committed generation of the run
-- (front_sizes, a JSON array, becomes the first front's size and the number of fronts)
SELECT g.generation AS generation,
       g.best_reward AS best_reward,
       g.mean_reward AS mean_reward,
       g.median_reward AS median_reward,
       json_extract(g.front_sizes, '$[0]') AS first_front_size,
       json_array_length(g.front_sizes) AS fronts,
       g.diversity_min AS diversity_min,
       g.diversity_max AS diversity_max,
       g.evaluations AS evaluations,
       g.wall_time AS wall_time,
       g.time_simulation AS time_simulation,
       g.time_kb AS time_kb,
       g.time_diversity AS time_diversity,
       g.time_selection AS time_selection,
       g.time_database AS time_database
FROM generation AS g
ORDER BY g.run_id, g.generation;
