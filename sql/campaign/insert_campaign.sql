INSERT INTO campaign (id, config, created) VALUES (1, :config, strftime('%Y-%m-%dT%H:%M:%SZ', 'now'))
