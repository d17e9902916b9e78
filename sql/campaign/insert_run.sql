INSERT INTO campaign_run (id, step, treatment, seed, file, generations, status)
VALUES (:id, :step, :treatment, :seed, :file, :generations, 'pending')
