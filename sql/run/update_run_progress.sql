UPDATE run
SET generations_done = :generations_done,
    evaluations = :evaluations,
    nan_outputs = :nan_outputs,
    status = :status,
    generations = :generations
WHERE id = :run_id
