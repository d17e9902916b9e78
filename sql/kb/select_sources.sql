SELECT source, run, first_generation, last_generation, policies FROM kb_source WHERE kb_id = :kb_id ORDER BY source
