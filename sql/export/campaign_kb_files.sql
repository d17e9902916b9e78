SELECT file FROM campaign_kb ORDER BY name
