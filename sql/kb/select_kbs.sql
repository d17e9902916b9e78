SELECT id, name, segment_width, channels, delta, match, randomized_seed FROM kb ORDER BY id
