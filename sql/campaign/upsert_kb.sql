INSERT INTO campaign_kb (name, file, made_from, segments, digest) VALUES (:name, :file, :made_from, :segments, :digest)
ON CONFLICT (name) DO UPDATE SET file = excluded.file, made_from = excluded.made_from,
    segments = excluded.segments, digest = excluded.digest
