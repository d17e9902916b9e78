SELECT id, name, segment_width, channels, delta, match, counting, randomized_seed FROM kb ORDER BY id
