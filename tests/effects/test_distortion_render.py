"""The pinhole render camera and the distortion warp: geometry to 1e-3 px, corners to
0.02 px mean, against OpenCV's projection (an independent implementation)."""

import cv2
import numpy as np
import pytest
from scipy import ndimage

from designer.core.distortion import BrownConrady, FisheyeEquidistant
from designer.core.interior import InteriorOrientation
from designer.effects.distortion_render import DistortionWarp, pinhole_render_camera
from designer.errors import DesignerError, NotInvertibleError
from tests.effects.distortion_scene import FISHEYE, LENSES, PP, H, W, expected_corners, scene
from tests.effects.synthetic import area_sampled, project_opencv, refine_corners
from tests.synthetic import pixel_camera


@pytest.fixture(scope="module", params=sorted(LENSES))
def warped(request):
    name = request.param
    interior = LENSES[name]
    render, warp = pinhole_render_camera(interior)
    pattern, _ = scene(name)
    image = warp.apply(area_sampled(render, pattern).astype(np.float32))
    return name, interior, render, warp, image


# ---------------------------------------------------------------------------- geometry
def test_without_distortion_nothing_is_paid():
    interior = pixel_camera(W, H, 800.0, None, PP)
    assert pinhole_render_camera(interior) == (interior, None)
    render, warp = pinhole_render_camera(pixel_camera(W, H, 800.0, BrownConrady(), PP))
    assert warp is None and render == interior


def test_render_camera_keeps_the_focal_length_and_covers_the_samples(warped):
    _, interior, render, warp, _ = warped
    assert render.distortion is None
    assert render.fx_px == pytest.approx(interior.fx_px, rel=1e-12)
    assert render.fy_px == pytest.approx(interior.fy_px, rel=1e-12)
    assert render.pixel_aspect is None  # square in, square out
    assert render.focal_length_mm == interior.focal_length_mm
    W_r, H_r = render.image_size_px
    # every sampled position is at least margin (2) + cubic reach (8) px inside, and the
    # image is less than two pixels larger than that (rounding up, grid alignment)
    lo_u, hi_u = warp.map_u_px.min(), warp.map_u_px.max()
    lo_v, hi_v = warp.map_v_px.min(), warp.map_v_px.max()
    assert min(lo_u, lo_v, W_r - hi_u, H_r - hi_v) >= 10.0 - 1e-9
    assert W_r - (hi_u - lo_u) - 20.0 < 2.0 and H_r - (hi_v - lo_v) - 20.0 < 2.0
    # near the principal point render pixels sit on output pixels: c_r − c is whole
    for d in (render.cx_px - interior.cx_px, render.cy_px - interior.cy_px):
        assert abs(d - round(d)) < 1e-9


def test_mapping_error_against_opencv(warped):
    """Forward check with OpenCV's projection: map position → undistorted normalised
    coordinates → cv2.projectPoints → must land on the output pixel centre (≤ 0.001 px)."""
    _, interior, render, warp, _ = warped
    assert warp.max_mapping_error_px <= 1e-3
    x = (warp.map_u_px - render.cx_px) / render.fx_px
    y = (warp.map_v_px - render.cy_px) / render.fy_px
    pts = np.column_stack([x.ravel(), y.ravel(), np.ones(x.size)])
    uv = project_opencv(interior, pts)
    v, u = np.mgrid[0:H, 0:W] + 0.5
    err = np.hypot(uv[:, 0] - u.ravel(), uv[:, 1] - v.ravel())
    assert err.max() <= 1e-3


def test_corners_of_the_warped_render_match_opencv(warped):
    """An area-sampled checkerboard rendered by the enlarged pinhole camera, warped, and
    its corners refined with cornerSubPix: |mean| ≤ 0.02 px, RMS ≤ 0.1 px against
    cv2.(fisheye.)projectPoints (OpenCV corners + 0.5 = designer pixels)."""
    name, interior, _, _, image = warped
    pattern, n = scene(name)
    uv, nb = expected_corners(interior, pattern, n)
    found, expected = refine_corners(image, uv, nb, np.random.default_rng(7))
    err = found - expected
    assert len(err) > 400
    assert np.abs(err.mean(axis=0)).max() <= 0.02
    assert np.sqrt((err**2).sum(axis=1).mean()) <= 0.1


def test_warp_agrees_with_a_direct_distorted_render(warped):
    """The same corners found in an image area-sampled directly through the lens model
    (what a perfect distorted renderer would give): no systematic shift (≤ 0.01 px); the
    RMS difference (~0.06 px) is cornerSubPix's response to two different samplings."""
    name, interior, _, _, image = warped
    pattern, n = scene(name)
    uv, nb = expected_corners(interior, pattern, n)
    direct = area_sampled(interior, pattern)
    a, _ = refine_corners(image, uv, nb, np.random.default_rng(7))
    b, _ = refine_corners(direct, uv, nb, np.random.default_rng(7))
    d = a - b
    assert np.abs(d.mean(axis=0)).max() <= 0.01
    assert np.sqrt((d**2).sum(axis=1).mean()) <= 0.1


# --------------------------------------------------------------------------- resampler
def test_resampler_is_exact_where_cv2_remap_is_not():
    """A ramp whose value is the pixel's own u coordinate: sampling it must return the map.
    map_coordinates (float64 positions) is exact to < 1e-6 px; cv2.remap quantises to
    1/32 px (±0.016 px), which is why the warp does not use it."""
    interior = LENSES["barrel"]
    render, warp = pinhole_render_camera(interior)
    W_r, H_r = render.image_size_px
    ramp = np.tile(np.arange(W_r) + 0.5, (H_r, 1))
    coords = np.stack([warp.map_v_px - 0.5, warp.map_u_px - 0.5])
    exact = ndimage.map_coordinates(ramp, coords, order=3, mode="nearest")
    assert np.abs(exact - warp.map_u_px).max() < 1e-6
    remapped = cv2.remap(ramp.astype(np.float32), (warp.map_u_px - 0.5).astype(np.float32),
                         (warp.map_v_px - 0.5).astype(np.float32), cv2.INTER_LINEAR)
    err = np.abs(remapped - warp.map_u_px)
    assert 0.01 < err.max() < 1 / 32 + 1e-3


def test_integer_images_keep_their_type():
    render, warp = pinhole_render_camera(LENSES["pincushion"])
    img = np.full(render.image_size_px[::-1] + (3,), 1000, np.uint16)
    out = warp.apply(img)
    assert out.dtype == np.uint16 and out.shape == (H, W, 3)
    assert (out == 1000).all()
    with pytest.raises(ValueError, match="expects"):
        warp.apply(np.zeros((H, W), np.float32))


# --------------------------------------------------------------------- oversampling, IO
def test_oversampled_warp_area_averages():
    interior = pixel_camera(160, 120, 160.0, BrownConrady(k1=-0.2), (1.3, 0.4))
    render1, warp1 = pinhole_render_camera(interior)
    render2, warp2 = pinhole_render_camera(interior, 2)
    assert render2.fx_px == pytest.approx(2 * interior.fx_px)
    assert warp2.map_u_px.shape == (240, 320) and warp2.output_size_px == (160, 120)
    assert warp2.max_mapping_error_px <= 1e-3
    # a smooth image gives the same result both ways
    def smooth(render):
        v, u = np.mgrid[0:render.image_size_px[1], 0:render.image_size_px[0]] + 0.5
        x, y = (u - render.cx_px) / render.fx_px, (v - render.cy_px) / render.fy_px
        return (0.5 + 0.2 * np.sin(3 * x) * np.cos(2 * y)).astype(np.float32)
    a, b = warp1.apply(smooth(render1)), warp2.apply(smooth(render2))
    assert np.abs(a - b).max() < 2e-3


@pytest.mark.parametrize("lens", [BrownConrady(k1=0.1, p2=0.001), FisheyeEquidistant(k1=0.02)])
def test_save_and_load_round_trip(tmp_path, lens):
    interior = pixel_camera(160, 120, 120.0, lens, (1.5, -2.0))
    render, warp = pinhole_render_camera(interior, 2, order=1)
    path = tmp_path / "warp.npz"
    warp.save(path)
    loaded = DistortionWarp.load(path, interior)
    assert loaded.render_interior == render
    np.testing.assert_array_equal(loaded.map_u_px, warp.map_u_px)
    np.testing.assert_array_equal(loaded.map_v_px, warp.map_v_px)
    assert (loaded.oversample, loaded.order) == (2, 1)
    assert loaded.max_mapping_error_px == warp.max_mapping_error_px
    other = pixel_camera(160, 120, 121.0, lens, (1.5, -2.0))
    with pytest.raises(DesignerError, match="another camera"):
        DistortionWarp.load(path, other)
    np.savez(tmp_path / "other.npz", a=np.zeros(3))
    with pytest.raises(DesignerError, match="not a designer distortion warp"):
        DistortionWarp.load(tmp_path / "other.npz")


def test_non_square_pixels():
    pitch = 0.01
    interior = InteriorOrientation(8.0, 320 * pitch, 240 * pitch * 1.1, 320, 240, 0.02, -0.01,
                                   pixel_aspect=1.1, distortion=BrownConrady(k1=-0.2, p1=1e-3))
    render, warp = pinhole_render_camera(interior)
    assert render.pixel_aspect == 1.1
    assert (render.fx_px, render.fy_px) == pytest.approx((interior.fx_px, interior.fy_px))
    x = (warp.map_u_px - render.cx_px) / render.fx_px
    y = (warp.map_v_px - render.cy_px) / render.fy_px
    uv = project_opencv(interior, np.column_stack([x.ravel(), y.ravel(), np.ones(x.size)]))
    v, u = np.mgrid[0:240, 0:320] + 0.5
    assert np.hypot(uv[:, 0] - u.ravel(), uv[:, 1] - v.ravel()).max() <= 1e-3


# ------------------------------------------------------------------------------ limits
def test_fisheye_field_beyond_150_degrees_is_refused():
    wide = pixel_camera(W, H, 330.0, FISHEYE)  # θ = 84.4° at the corners
    with pytest.raises(DesignerError, match=r"84\.4° off axis.*168\.8° field.*up to 150°"):
        pinhole_render_camera(wide)
    with pytest.raises(DesignerError, match=r"143\.0° off axis.*pinhole"):  # beyond 180°
        pinhole_render_camera(pixel_camera(W, H, 200.0, FisheyeEquidistant()))
    with pytest.raises(NotInvertibleError, match="161320 of 480000 output pixels"):
        pinhole_render_camera(pixel_camera(W, H, 200.0, FISHEYE))  # this lens folds before


def test_fold_over_is_reported_with_the_pixel_count():
    # k1 = -0.5: the radial map peaks at distorted radius 0.544; the corners lie beyond
    folding = pixel_camera(W, H, 700.0, BrownConrady(k1=-0.5))
    with pytest.raises(NotInvertibleError, match=r"^\d+ of 480000 output pixels"):
        pinhole_render_camera(folding)
