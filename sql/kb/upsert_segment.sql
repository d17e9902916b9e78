INSERT INTO kb_segment (kb_id, id, cum_reward, count, first_source, first_generation, last_source,
                        last_generation, segment_values)
VALUES (:kb_id, :id, :cum_reward, :count, :first_source, :first_generation, :last_source, :last_generation,
        :segment_values)
ON CONFLICT (kb_id, id) DO UPDATE SET
    cum_reward = excluded.cum_reward, count = excluded.count,
    last_source = excluded.last_source, last_generation = excluded.last_generation
