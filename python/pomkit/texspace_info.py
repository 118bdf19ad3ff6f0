"""Sizes of the NCS texture-space maps (mirrors src/texspace.rs)."""

MAP_SIZE = 512
MAP_BYTES = {"size": MAP_SIZE, "bytes": 2 * MAP_SIZE * MAP_SIZE * 16}
