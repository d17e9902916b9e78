-- stepstone export --what kb: one row per segment of every KB of a file, with the runs
-- that inserted it and last credited it (the segment's values are not exported)
SELECT k.name AS kb,
       s.id AS segment,
       s.count AS count,
       s.cum_reward AS cum_reward,
       s.average_reward AS average_reward,
       fs.run AS first_run,
       s.first_generation AS first_generation,
       ls.run AS last_run,
       s.last_generation AS last_generation
FROM kb_segment AS s
JOIN kb AS k ON k.id = s.kb_id
LEFT JOIN kb_source AS fs ON fs.kb_id = s.kb_id AND fs.source = s.first_source
LEFT JOIN kb_source AS ls ON ls.kb_id = s.kb_id AND ls.source = s.last_source
ORDER BY k.name, s.id;
