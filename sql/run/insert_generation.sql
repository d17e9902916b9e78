INSERT INTO generation (run_id, generation, best_reward, mean_reward, median_reward, front_sizes,
                        diversity_min, diversity_max, evaluations, wall_time)
VALUES (:run_id, :generation, :best_reward, :mean_reward, :median_reward, :front_sizes,
        :diversity_min, :diversity_max, :evaluations, :wall_time)
