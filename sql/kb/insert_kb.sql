INSERT INTO kb (name, segment_width, channels, delta, match, counting, randomized_seed, created)
VALUES (:name, :segment_width, :channels, :delta, :match, :counting, :randomized_seed, strftime('%Y-%m-%dT%H:%M:%SZ', 'now'))
