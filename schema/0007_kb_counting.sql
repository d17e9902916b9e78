-- 0007: a knowledge base's counting rule (what observe credits when one policy's
-- segments match a KB segment several times): 'occurrence' (every match, as every
-- older KB was built) or 'policy' (the policy once: the paper's footnote 1).
ALTER TABLE kb ADD COLUMN counting TEXT NOT NULL DEFAULT 'occurrence'
    CHECK (counting IN ('occurrence', 'policy'));
