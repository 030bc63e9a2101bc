"""Scene generation: terrain (procedural, DEM, mesh), ground texture and GCP targets.

Plain functions that take and return data (numpy arrays, :class:`Heightfield`,
:class:`TerrainMesh`); reading and writing project files is the caller's business.
World frame everywhere: X east, Y north, Z up, metres, float64 (docs/conventions.md).
"""
