-- Every run of a campaign, in plan order: its plan and where it stands.
SELECT id, step, treatment, seed, file, generations, status, generations_done, best_reward, digest,
       wall_time, error
FROM campaign_run
ORDER BY id;
