INSERT INTO kb_source (kb_id, source, run, first_generation, last_generation, policies)
VALUES (:kb_id, :source, :run, :first_generation, :last_generation, :policies)
ON CONFLICT (kb_id, source) DO UPDATE SET
    run = excluded.run, first_generation = excluded.first_generation,
    last_generation = excluded.last_generation, policies = excluded.policies
