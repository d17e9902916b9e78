-- stepstone export --what individuals of a file older than schema 0005: the same
-- columns as individuals.sql, the milestones empty (the file did not record them)
SELECT i.id AS id,
       i.generation AS generation,
       i.parent_id AS parent_id,
       i.reward AS reward,
       i.fitness AS fitness,
       i.diversity AS diversity,
       i.r_max AS r_max,
       i.balls AS balls,
       i.steps AS steps,
       NULL AS presses,
       NULL AS pickups,
       NULL AS carry_steps,
       NULL AS basket_releases
FROM individual AS i
ORDER BY i.run_id, i.id;
