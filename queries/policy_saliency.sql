-- Saliency of one policy along time (the paper's Fig. 5): for each segment of
-- a stored policy, the average reward of the KB segment it matched. Needs the
-- rows written by `stepstone kb annotate RUN.db --kb KB.db` (policy_segment);
-- the KB is the copy that annotate keeps in the run file under its name.
--
-- Parameters:
--   :kb_name        name of the knowledge base in the run file
--   :individual_id  the policy (individual.id; `stepstone shape` prints it)
--
-- Result columns (in time order):
--   segment         index of the segment in the policy's behaviour
--   step_start      its first time step (segment x segment_width)
--   step_end        one past its last time step
--   kb_segment_id   the matched KB segment, NULL when none lies within delta
--   distance        Euclidean distance to it (0 when NULL)
--   average_reward  its average reward: the segment's saliency (0 when NULL)
--
-- sqlite3 run.db -cmd ".parameter set :kb_name 'run'" -cmd ".parameter set :individual_id 12" \
--         < queries/policy_saliency.sql
SELECT ps.segment                           AS segment,
       ps.segment * k.segment_width         AS step_start,
       (ps.segment + 1) * k.segment_width   AS step_end,
       ps.kb_segment_id                     AS kb_segment_id,
       ps.distance                          AS distance,
       ps.average_reward                    AS average_reward
FROM policy_segment AS ps
JOIN kb AS k ON k.id = ps.kb_id
WHERE k.name = :kb_name AND ps.individual_id = :individual_id
ORDER BY ps.segment;
