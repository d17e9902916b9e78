SELECT generation, state FROM checkpoint WHERE run_id = :run_id
