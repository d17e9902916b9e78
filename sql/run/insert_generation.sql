INSERT INTO generation (run_id, generation, best_reward, mean_reward, median_reward, front_sizes,
                        diversity_min, diversity_max, evaluations, wall_time, time_simulation, time_kb,
                        time_diversity, time_selection, time_database)
VALUES (:run_id, :generation, :best_reward, :mean_reward, :median_reward, :front_sizes,
        :diversity_min, :diversity_max, :evaluations, :wall_time, :time_simulation, :time_kb,
        :time_diversity, :time_selection, :time_database)
