-- Most salient segments: the segments of a knowledge base with the highest
-- average reward (the paper's saliency, cum_reward / count), among those seen
-- at least :min_count times, with where each came from.
--
-- Parameters:
--   :kb_name    name of the knowledge base ('run' in a run file; see kb.name)
--   :min_count  minimum number of policies credited to a segment (1 keeps all)
--   :limit      number of rows
--
-- Result columns (best first; ties: higher count, then lower id):
--   kb_segment_id     the segment's id in the KB
--   average_reward    cum_reward / count
--   count             policies credited to it
--   cum_reward        sum of their rewards
--   first_run         run whose observation inserted it (kb_source.run)
--   first_generation  generation of that observation
--   last_generation   generation of the latest observation credited to it
--
-- sqlite3 kb.db -cmd ".parameter set :kb_name 'run'" -cmd ".parameter set :min_count 5" \
--         -cmd ".parameter set :limit 20" < queries/salient_segments.sql
SELECT s.id             AS kb_segment_id,
       s.average_reward AS average_reward,
       s.count          AS count,
       s.cum_reward     AS cum_reward,
       src.run          AS first_run,
       s.first_generation,
       s.last_generation
FROM kb AS k
JOIN kb_segment AS s ON s.kb_id = k.id
JOIN kb_source AS src ON src.kb_id = k.id AND src.source = s.first_source
WHERE k.name = :kb_name AND s.count >= :min_count
ORDER BY s.average_reward DESC, s.count DESC, s.id ASC
LIMIT :limit;
