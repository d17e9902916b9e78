INSERT INTO kb (name, segment_width, channels, delta, match, randomized_seed, created)
VALUES (:name, :segment_width, :channels, :delta, :match, :randomized_seed, strftime('%Y-%m-%dT%H:%M:%SZ', 'now'))
