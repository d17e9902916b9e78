-- A run's policies per generation and those that pressed the switch, picked a
-- ball up, released one within the basket radius and collected one (schema 0005)
SELECT generation, count(*), sum(presses > 0), sum(pickups > 0), sum(basket_releases > 0), sum(balls > 0)
FROM individual
WHERE run_id = :run_id
GROUP BY generation
ORDER BY generation
