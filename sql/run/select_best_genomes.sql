-- the stored genomes of a run, highest task reward first, lower individual id on ties (a seed's `best`)
SELECT g.individual_id, g.genome, i.reward, i.balls, i.generation
FROM genome AS g JOIN individual AS i ON i.run_id = g.run_id AND i.id = g.individual_id
WHERE g.run_id = :run_id
ORDER BY i.reward DESC, i.id ASC
LIMIT :count
