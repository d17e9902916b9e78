SELECT count(*) FROM kb_segment WHERE kb_id = :kb_id
