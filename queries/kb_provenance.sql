-- Provenance of a knowledge base: the runs that fed it, the generations
-- observed from each and how many policies, with the segments each run
-- inserted and the segments whose latest credit came from it.
--
-- Parameters:
--   :kb_name  name of the knowledge base (kb.name; a KB file holds one)
--
-- Result columns (in the order the sources were added):
--   source               source index within the KB
--   run                  run name
--   first_generation     first generation observed from it
--   last_generation      last generation observed from it
--   policies             policies observed from it
--   segments_inserted    KB segments its observations inserted
--   segments_last_credited  KB segments last credited by it
--   randomized_seed      the KB's randomize seed (NULL unless `kb randomize` made it)
--   created              when the KB was written (UTC)
--
-- sqlite3 merged.db -cmd ".parameter set :kb_name 'run'" < queries/kb_provenance.sql
SELECT src.source,
       src.run,
       src.first_generation,
       src.last_generation,
       src.policies,
       (SELECT count(*) FROM kb_segment AS s WHERE s.kb_id = k.id AND s.first_source = src.source)
           AS segments_inserted,
       (SELECT count(*) FROM kb_segment AS s WHERE s.kb_id = k.id AND s.last_source = src.source)
           AS segments_last_credited,
       k.randomized_seed,
       k.created
FROM kb AS k
JOIN kb_source AS src ON src.kb_id = k.id
WHERE k.name = :kb_name
ORDER BY src.source;
