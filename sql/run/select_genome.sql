SELECT g.genome, i.reward, i.balls, i.generation
FROM genome AS g JOIN individual AS i ON i.run_id = g.run_id AND i.id = g.individual_id
WHERE g.run_id = :run_id AND g.individual_id = :individual_id
