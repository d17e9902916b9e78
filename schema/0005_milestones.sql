-- 0005: the steps of the task each evaluated individual reached, summed over
-- its starts (docs/simulator.md: milestones). Rows written by older versions
-- hold NULL: their milestones were not recorded.

ALTER TABLE individual ADD COLUMN presses         INTEGER;  -- switch presses
ALTER TABLE individual ADD COLUMN pickups         INTEGER;  -- balls picked up
ALTER TABLE individual ADD COLUMN carry_steps     INTEGER;  -- steps ending with a ball carried
ALTER TABLE individual ADD COLUMN basket_releases INTEGER;  -- releases within the basket radius, scoring or not
