-- The knowledge bases a campaign made ('kb' and 'kb-rand').
SELECT name, file, made_from, segments, digest FROM campaign_kb ORDER BY name;
