-- Salient positions of the arena: the average saliency of a policy per time
-- window (the paper's Figs. 4 and 8 colour the trajectory by it). Needs the
-- rows of `stepstone kb annotate` (policy_segment). Segments are grouped into
-- windows of :window steps (a multiple of the KB's segment width is best).
--
-- The run file stores no poses: replay the policy to get them, then join its
-- steps to the windows. The behaviour, hence every segment, is the first
-- start's (CSV column start = 1); row `step` of the CSV is time step `step`.
--
--   stepstone replay run.db --individual 12 --csv steps.csv
--   sqlite3 run.db
--     .import --csv --schema temp steps.csv replay_step
--     .parameter set :kb_name 'run'
--     .parameter set :individual_id 12
--     .parameter set :window 100
--     WITH w AS (<this query, without its final semicolon>)
--     SELECT w.window_index, avg(p.x) AS x, avg(p.y) AS y, w.average_saliency
--     FROM w
--     JOIN temp.replay_step AS p
--       ON p.start = 1 AND p.step >= w.step_start AND p.step < w.step_end
--     GROUP BY w.window_index ORDER BY w.window_index;
--
-- SQLite allows no parameters in views, hence the CTE. A policy that stopped
-- early (after 100 still steps) has no CSV rows after its last step; its
-- behaviour repeats the last row there.
--
-- Parameters:
--   :kb_name        name of the knowledge base in the run file
--   :individual_id  the policy
--   :window         steps per window (>= 1)
--
-- Result columns (in time order):
--   window_index        step_start / :window
--   step_start          first step of the window's first segment
--   step_end            one past the last step of its last segment
--   segments            segments in the window
--   average_saliency    mean of their average rewards (unmatched count 0)
--   max_saliency        the largest of them
--   unmatched_segments  segments with no KB segment within delta
SELECT (ps.segment * k.segment_width) / :window    AS window_index,
       min(ps.segment) * k.segment_width          AS step_start,
       (max(ps.segment) + 1) * k.segment_width    AS step_end,
       count(*)                                   AS segments,
       avg(ps.average_reward)                     AS average_saliency,
       max(ps.average_reward)                     AS max_saliency,
       sum(ps.kb_segment_id IS NULL)              AS unmatched_segments
FROM policy_segment AS ps
JOIN kb AS k ON k.id = ps.kb_id
WHERE k.name = :kb_name AND ps.individual_id = :individual_id
GROUP BY window_index
ORDER BY window_index;
