"""Cycles validation experiments: is what Cycles renders what the photogrammetric model says?

Three experiments after the original study (docs/validation.md), each a plain function
returning its figures and pass/fail, wrapped by ``designer validate``:

* ``projection``: corners of checkerboards on the inside walls of a 10 m cube, found in
  rendered images by a Harris detector with sub-pixel refinement, against
  ``designer.core.projection``; plus the detector's own error on exactly area-sampled
  synthetic checkerboards (``synthetic``), compared by a variance test;
* ``psf``: a sphere inside one pixel's viewing cone lights only that pixel;
* ``texture``: a checkerboard texture with 'Closest' interpolation stays pure black and
  white with its edges where the projection puts them.

Only ``designer.render.worker`` imports bpy; everything here is numpy, OpenCV, scipy and
matplotlib, and renders through ``designer.render.runner``.
"""
