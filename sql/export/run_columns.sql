-- task, treatment and seed of a run file, the first columns of its exported rows
SELECT task, treatment, seed FROM run
