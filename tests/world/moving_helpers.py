"""A small timed project with one flat red box driving east under a nadir camera, and how
much of each rendered pixel the box covers."""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path

import cv2
import numpy as np

from designer.project import model as m
from tests.world.helpers import ORIGIN, timed_survey

#: the box: 1 m square, 1 cm tall, so its silhouette is its level top face
BOX_SIZE_M = (1.0, 1.0, 0.01)
RED = (0.9, 0.02, 0.02)
SPEED_M_S = 1.5


def moving_project(times_s=(0.0, 2.0), speed_m_s=SPEED_M_S, samples=16) -> m.Project:
    """Two nadir photos 30 m above the origin (160 x 120 px, 6 cm/px) and a red box
    moving east on flat ground along Y = N0 + 0.5 from X = E0 − 2.5 at ``speed_m_s``."""
    p = timed_survey(times_s, sun_over_time=False)
    E0, N0, H0 = ORIGIN
    box = m.MovingObject("box1", (m.PathPoint(E0 - 2.5, N0 + 0.5), m.PathPoint(E0 + 8, N0 + 0.5)),
                         speed_m_s, shape="box", size_m=BOX_SIZE_M, albedo_rgb=RED)
    texture = m.Texture(m.ProceduralTexture("noise", seed=2, texel_size_m=0.02), 4, 4, "linear")
    terrain = replace(p.scene.terrain, source=m.FlatTerrain(H0 + 0.25))
    return replace(p, scene=replace(p.scene, texture=texture, targets=None, terrain=terrain,
                                    moving_objects=(box,)),
                   render=replace(p.render, samples=samples))


def srgb_to_linear(image_u8: np.ndarray) -> np.ndarray:
    c = image_u8.astype(float) / 255.0
    return np.where(c <= 0.04045, c / 12.92, ((c + 0.055) / 1.055) ** 2.4)


def linear_rgb(path: Path) -> np.ndarray:
    """The 8-bit sRGB image at ``path`` as linear RGB (H, W, 3) in 0..1."""
    return srgb_to_linear(cv2.imread(str(path))[:, :, ::-1])


def box_coverage(image: Path, ground: Path) -> np.ndarray:
    """Per pixel, the fraction covered by the red box: the render is the box's colour and
    the bare ground's mixed in linear light (box pixel filter), so the fraction is the
    least-squares mix of the two."""
    img, bg = linear_rgb(image), linear_rgb(ground)
    d = np.array(RED) - bg
    return np.clip(((img - bg) * d).sum(-1) / (d * d).sum(-1), 0, 1)
