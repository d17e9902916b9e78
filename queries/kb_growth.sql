-- KB growth per generation: how many segments each observed generation
-- inserted into a knowledge base, and the KB's size after it. A segment
-- counts in the generation (of its source run) whose observation inserted it
-- (kb_segment.first_generation); segments only credited later do not grow the
-- KB. For a merged KB, the sources follow each other in merge order.
--
-- Parameters:
--   :kb_name  name of the knowledge base ('run' in a run file)
--
-- Result columns (in source order, then generation):
--   run         source run (kb_source.run)
--   generation  generation of that run
--   inserted    segments first seen in that generation
--   kb_size     segments in the KB after it (running total)
--
-- sqlite3 run.db -cmd ".parameter set :kb_name 'run'" < queries/kb_growth.sql
SELECT src.run                AS run,
       s.first_generation     AS generation,
       count(*)               AS inserted,
       sum(count(*)) OVER (ORDER BY s.first_source, s.first_generation) AS kb_size
FROM kb AS k
JOIN kb_segment AS s ON s.kb_id = k.id
JOIN kb_source AS src ON src.kb_id = k.id AND src.source = s.first_source
WHERE k.name = :kb_name
GROUP BY s.first_source, s.first_generation
ORDER BY s.first_source, s.first_generation;
