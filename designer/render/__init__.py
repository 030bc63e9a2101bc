"""Rendering with Blender/Cycles.

Only ``designer.render.worker`` imports ``bpy``; it runs in its own process and reads
a job description prepared by the rest of this package.
"""
