SELECT individual_id FROM genome WHERE run_id = :run_id ORDER BY individual_id
