"""Photogrammetric core: cameras, distortion, rotations, projection, height fields and
ray queries on them (:mod:`.raycast`). numpy only (and the compiled terrain kernels).

Importing this package must never import bpy, Qt, OpenCV or pyvista (a test checks).
"""
