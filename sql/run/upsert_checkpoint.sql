INSERT INTO checkpoint (run_id, generation, state) VALUES (:run_id, :generation, :state)
ON CONFLICT (run_id) DO UPDATE SET generation = excluded.generation, state = excluded.state
