INSERT INTO individual (run_id, id, generation, parent_id, reward, fitness, diversity, shaping, balls, steps)
VALUES (:run_id, :id, :generation, :parent_id, :reward, :fitness, :diversity, :shaping, :balls, :steps)
