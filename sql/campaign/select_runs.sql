SELECT id, step, treatment, seed, file, generations, status FROM campaign_run ORDER BY id
