-- Where a probe run's file keeps its bytes (campaign --dry-run's disk estimate), by the
-- pages of each table and its indexes (the dbstat virtual table).
-- Columns: individual_bytes (the rows of every evaluation), generation_bytes (genomes and
-- generation rows), kb_bytes (the KB's segments and provenance), total_bytes (the whole file).
SELECT coalesce(sum(CASE WHEN name IN ('individual', 'individual_by_generation') THEN pgsize END), 0)
           AS individual_bytes,
       coalesce(sum(CASE WHEN name IN ('genome', 'generation') OR name LIKE 'sqlite_autoindex_genome%'
                          OR name LIKE 'sqlite_autoindex_generation%' THEN pgsize END), 0) AS generation_bytes,
       coalesce(sum(CASE WHEN name LIKE 'kb%' OR name LIKE 'sqlite_autoindex_kb%' THEN pgsize END), 0)
           AS kb_bytes,
       coalesce(sum(pgsize), 0) AS total_bytes
FROM dbstat;
