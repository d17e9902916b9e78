INSERT OR IGNORE INTO genome (run_id, individual_id, genome) VALUES (:run_id, :individual_id, :genome)
