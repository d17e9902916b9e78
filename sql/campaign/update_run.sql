UPDATE campaign_run
SET status = :status, generations_done = :generations_done, best_reward = :best_reward, digest = :digest,
    wall_time = wall_time + :wall_time, error = :error
WHERE id = :id
