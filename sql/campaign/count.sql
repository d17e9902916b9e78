SELECT count(*) FROM campaign
