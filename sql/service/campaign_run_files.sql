SELECT id, file FROM campaign_run ORDER BY id
