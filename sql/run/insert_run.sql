INSERT INTO run (task, treatment, seed, config, status, generations, program_version, created)
VALUES (:task, :treatment, :seed, :config, 'running', :generations, :program_version,
        strftime('%Y-%m-%dT%H:%M:%SZ', 'now'))
