"""designer: repeatable, photogrammetrically exact virtual surveys for SfM experiments.

Layers (arrows point one way): ``designer.core`` (numpy-only geometry) is used by
everything else; only the render worker imports ``bpy`` and only the GUI imports Qt.
"""

__version__ = "0.1.0"
