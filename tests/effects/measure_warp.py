"""Print the distortion warp's measured accuracy and the resampler comparison.

Run: PYTHONPATH=. python -m tests.effects.measure_warp

For each test lens: the forward check against OpenCV, then checkerboard corners
(cornerSubPix) against cv2.(fisheye.)projectPoints for an image area-sampled directly
through the lens model (the detector's own floor) and for the warped pinhole render with
each resampler; "vs direct" pairs the same corners in the two images.
"""

from __future__ import annotations

import cv2
import numpy as np

from designer.effects.distortion_render import pinhole_render_camera
from tests.effects.distortion_scene import LENSES, H, W, expected_corners, scene
from tests.effects.synthetic import area_sampled, project_opencv, refine_corners


def _stats(err: np.ndarray) -> str:
    rms = np.sqrt((err**2).sum(1).mean())
    return (f"mean ({err[:, 0].mean():+.4f}, {err[:, 1].mean():+.4f}) rms {rms:.4f} "
            f"max {np.hypot(*err.T).max():.3f}")


def _forward_check(interior, render, warp) -> float:
    x = (warp.map_u_px - render.cx_px) / render.fx_px
    y = (warp.map_v_px - render.cy_px) / render.fy_px
    uv = project_opencv(interior, np.column_stack([x.ravel(), y.ravel(), np.ones(x.size)]))
    v, u = np.mgrid[0:H, 0:W] + 0.5
    return float(np.hypot(uv[:, 0] - u.ravel(), uv[:, 1] - v.ravel()).max())


def _ramp_error(render, warp, interp) -> float:
    W_r, H_r = render.image_size_px
    ramp = np.tile(np.arange(W_r, dtype=np.float32) + 0.5, (H_r, 1))
    out = cv2.remap(ramp, (warp.map_u_px - 0.5).astype(np.float32),
                    (warp.map_v_px - 0.5).astype(np.float32), interp)
    return float(np.abs(out - warp.map_u_px).max())


def main() -> None:
    for name in ("barrel", "pincushion", "tangential", "fisheye150"):
        interior = LENSES[name]
        pattern, n = scene(name)
        uv, nb = expected_corners(interior, pattern, n)
        ref, expected = refine_corners(area_sampled(interior, pattern), uv, nb,
                                       np.random.default_rng(7))
        render, warp = pinhole_render_camera(interior)
        opencv = _forward_check(interior, render, warp)
        print(f"{name}: render {render.image_size_px}, forward check "
              f"{warp.max_mapping_error_px:.2e} px (own), {opencv:.2e} px (OpenCV); "
              f"ramp error cv2.remap linear "
              f"{_ramp_error(render, warp, cv2.INTER_LINEAR):.4f} px, cubic "
              f"{_ramp_error(render, warp, cv2.INTER_CUBIC):.4f} px")
        print(f"   {'direct render (detector floor)':34s} {_stats(ref - expected)}  n={len(ref)}")
        variants = {}
        for oversample, order in ((1, 1), (1, 3), (2, 3)):
            render, warp = pinhole_render_camera(interior, oversample, order=order)
            img = area_sampled(render, pattern).astype(np.float32)
            variants[f"map_coordinates order {order} os {oversample}"] = warp.apply(img)
            if (oversample, order) == (1, 3):
                for interp, label in ((cv2.INTER_LINEAR, "linear"), (cv2.INTER_CUBIC, "cubic")):
                    variants[f"cv2.remap {label} os 1"] = cv2.remap(
                        img, (warp.map_u_px - 0.5).astype(np.float32),
                        (warp.map_v_px - 0.5).astype(np.float32), interp,
                        borderMode=cv2.BORDER_REPLICATE)
        for label, img in variants.items():
            found, _ = refine_corners(img, uv, nb, np.random.default_rng(7))
            print(f"   {label:34s} {_stats(found - expected)} | vs direct {_stats(found - ref)}")


if __name__ == "__main__":
    main()
