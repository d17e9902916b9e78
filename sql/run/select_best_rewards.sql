SELECT generation, best_reward FROM generation WHERE run_id = :run_id ORDER BY generation
