INSERT OR REPLACE INTO policy_segment (run_id, individual_id, kb_id, segment, kb_segment_id, distance, average_reward)
VALUES (:run_id, :individual_id, :kb_id, :segment, :kb_segment_id, :distance, :average_reward)
