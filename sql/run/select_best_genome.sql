SELECT g.individual_id
FROM genome AS g JOIN individual AS i ON i.run_id = g.run_id AND i.id = g.individual_id
WHERE g.run_id = :run_id
ORDER BY i.reward DESC, i.id ASC
LIMIT 1
