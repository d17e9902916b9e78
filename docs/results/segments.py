"""Decoding kb_segment.segment_values (docs/schema.md: segment values) with the
standard library: raw float32 (width x channels x 4 bytes) or packed behind 'P'
(binary channels one bit a step, the others float32)."""
import struct


def decode(blob, width, channels):
    """The segment's width x channels values, row-major, as a list of floats."""
    if len(blob) == width * channels * 4:
        return list(struct.unpack(f"<{width * channels}f", blob))
    if blob[0:1] != b"P":
        raise ValueError(f"a segment of {len(blob)} bytes is neither raw nor packed")
    at = 1 + (channels + 7) // 8
    binary = [blob[1 + c // 8] >> (c % 8) & 1 for c in range(channels)]
    out = [0.0] * (width * channels)
    for c in range(channels):
        if binary[c]:
            for r in range(width):
                out[r * channels + c] = float(blob[at + r // 8] >> (r % 8) & 1)
            at += (width + 7) // 8
    for c in range(channels):
        if not binary[c]:
            for r, v in enumerate(struct.unpack(f"<{width}f", blob[at:at + 4 * width])):
                out[r * channels + c] = v
            at += 4 * width
    return out
