-- 0006: kb_segment.segment_values may hold a segment packed: its binary channels
-- (all values exactly 0 or 1) as one bit a step, the others as float32, behind the
-- tag byte 'P' (docs/schema.md: segment values). A blob of exactly
-- segment_width x channels x 4 bytes is the raw float32 form, as every older file
-- holds; SQL reads either as float32 through segment_floats(blob, width, channels).
-- No table changes: the version tells older programs that they cannot read the
-- packed form, and they refuse the file instead of misreading it.
SELECT 1;
