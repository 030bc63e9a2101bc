"""Photogrammetric core: cameras, distortion, rotations, projection. numpy only.

Importing this package must never import bpy, Qt, OpenCV or pyvista (a test checks).
"""
