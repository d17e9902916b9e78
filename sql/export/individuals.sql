-- stepstone export --what individuals: one row per evaluated individual (NULL parent_id
-- for generation 0, NULL shaping without a shaping KB: empty CSV fields)
SELECT i.id AS id,
       i.generation AS generation,
       i.parent_id AS parent_id,
       i.reward AS reward,
       i.fitness AS fitness,
       i.diversity AS diversity,
       i.shaping AS shaping,
       i.balls AS balls,
       i.steps AS steps
FROM individual AS i
ORDER BY i.run_id, i.id;
