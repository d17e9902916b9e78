SELECT count(*) FROM generation
