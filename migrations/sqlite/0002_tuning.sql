-- The research options of a job request moved into its `tuning` object:
-- options.patience → tuning.search_patience, options.polish → polish_budget,
-- options.refine → refine_budget, options.correction, options.initial_step,
-- options.start and the top-level objective keep their names. Requests
-- stored before (a queued job resumes from its request) are rewritten so
-- that they still parse; absent options become nulls, which mean "the
-- preset's".
UPDATE jobs
SET request = json_remove(
        json_set(request, '$.tuning', json_object(
            'search_patience', request -> '$.options.patience',
            'polish_budget', request -> '$.options.polish',
            'refine_budget', request -> '$.options.refine',
            'correction', request -> '$.options.correction',
            'initial_step', request -> '$.options.initial_step',
            'start', request -> '$.options.start',
            'objective', request -> '$.objective')),
        '$.options.patience', '$.options.polish', '$.options.refine',
        '$.options.correction', '$.options.initial_step', '$.options.start',
        '$.objective')
WHERE json_type(request, '$.tuning') IS NULL
  AND (json_type(request, '$.objective') IS NOT NULL
       OR json_type(request, '$.options.patience') IS NOT NULL
       OR json_type(request, '$.options.polish') IS NOT NULL
       OR json_type(request, '$.options.refine') IS NOT NULL
       OR json_type(request, '$.options.correction') IS NOT NULL
       OR json_type(request, '$.options.initial_step') IS NOT NULL
       OR json_type(request, '$.options.start') IS NOT NULL);
