SELECT id, cum_reward, count, first_source, first_generation, last_source, last_generation, segment_values
FROM kb_segment WHERE kb_id = :kb_id ORDER BY id
