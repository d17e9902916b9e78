SELECT id, task, treatment, seed, config, status, generations, generations_done, evaluations, nan_outputs
FROM run ORDER BY id
