-- How far a run's policies get through the task: per run and generation, the policies
-- evaluated and how many of them pressed the switch, picked a ball up, carried one,
-- released one within the basket radius and collected one (docs/simulator.md: milestones).
-- Parameters: none (every run of the file). Files older than schema 0005: run
-- `stepstone db migrate FILE` first; their milestones then read NULL, and so do the
-- counts (not 0).
-- Columns: run_id, generation, policies, pressed, picked_up, carried, released_at_basket,
--          collected, mean_carry_steps.
SELECT run_id,
       generation,
       count(*)                                       AS policies,
       sum(presses > 0)                               AS pressed,
       sum(pickups > 0)                               AS picked_up,
       sum(carry_steps > 0)                           AS carried,
       sum(basket_releases > 0)                       AS released_at_basket,
       sum(balls > 0)                                 AS collected,
       avg(carry_steps)                               AS mean_carry_steps
FROM individual
GROUP BY run_id, generation
ORDER BY run_id, generation;
