-- stepstone export --what individuals: one row per evaluated individual (NULL parent_id
-- for generation 0, NULL r_max without a shaping KB: empty CSV fields), with its
-- milestones summed over its starts (docs/simulator.md: milestones)
SELECT i.id AS id,
       i.generation AS generation,
       i.parent_id AS parent_id,
       i.reward AS reward,
       i.fitness AS fitness,
       i.diversity AS diversity,
       i.r_max AS r_max,
       i.balls AS balls,
       i.steps AS steps,
       i.presses AS presses,
       i.pickups AS pickups,
       i.carry_steps AS carry_steps,
       i.basket_releases AS basket_releases
FROM individual AS i
ORDER BY i.run_id, i.id;
