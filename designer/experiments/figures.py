"""The validation figures (PNG): matplotlib's Agg canvas, no pyplot, no global state."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from designer.atomic import atomic_path

DPI = 110
CAMERA_COLOURS = ["tab:blue", "tab:orange", "tab:green", "tab:red", "tab:purple",
                  "tab:brown", "tab:pink", "tab:gray"]


def figure(width_in: float, height_in: float):
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    fig = Figure(figsize=(width_in, height_in), dpi=DPI)
    FigureCanvasAgg(fig)
    return fig


def save(fig, path: Path) -> Path:
    fig.tight_layout()
    with atomic_path(path) as tmp:
        fig.savefig(tmp, format="png")
    return path


# ---------------------------------------------------------------------- projection
def corners_on_image(path: Path, gray: np.ndarray, uv_proj: np.ndarray, uv_det: np.ndarray,
                     title: str) -> Path:
    """A rendered image with projected (circles) and detected (crosses) corners, and an
    enlarged view of one corner."""
    fig = figure(11, 4.6)
    ax, zoom = fig.add_subplot(1, 2, 1), fig.add_subplot(1, 2, 2)
    H, W = gray.shape
    for a in (ax, zoom):
        a.imshow(gray, cmap="gray", vmin=0, vmax=255, interpolation="nearest",
                 extent=(0, W, H, 0))
        a.plot(uv_proj[:, 0], uv_proj[:, 1], "o", mfc="none", mec="tab:red", ms=9,
               label="projected (camera model)")
        a.plot(uv_det[:, 0], uv_det[:, 1], "x", color="tab:cyan", ms=7, mew=1.5,
               label="detected (Harris + sub-pixel)")
    ax.set_title(title)
    ax.set_xlim(0, W)
    ax.set_ylim(H, 0)
    ax.legend(loc="lower right", fontsize=8)
    centre = uv_proj[np.argmin(np.linalg.norm(uv_proj - [W / 2, H / 2], axis=1))]
    zoom.set_xlim(centre[0] - 4, centre[0] + 4)
    zoom.set_ylim(centre[1] + 4, centre[1] - 4)
    zoom.set_xticks(np.arange(np.floor(centre[0] - 4), centre[0] + 5))
    zoom.set_yticks(np.arange(np.floor(centre[1] - 4), centre[1] + 5))
    zoom.grid(True, color="tab:olive", lw=0.5, alpha=0.7)
    zoom.set_title("one corner, 8 × 8 px (grid lines = pixel edges)")
    return save(fig, path)


def error_vectors(path: Path, uv: np.ndarray, d: np.ndarray, camera: np.ndarray,
                  names: list[str], size_px: tuple[int, int]) -> Path:
    """Left: each corner's error vector (detected − projected), enlarged; right: the mean
    vector in each of 6 × 4 image cells, enlarged 10× more — a wrong camera mapping shows
    as a pattern (all one way, or radial)."""
    W, H = size_px
    scale = 0.5 * W  # a 0.1 px error is drawn 5 % of the image width long
    fig = figure(13, 5.2)
    ax, bx = fig.add_subplot(1, 2, 1), fig.add_subplot(1, 2, 2)
    for s, name in enumerate(names):
        m = camera == s
        if m.any():
            ax.quiver(uv[m, 0], uv[m, 1], d[m, 0], d[m, 1], angles="xy", scale_units="xy",
                      scale=1 / scale, width=0.002, color=CAMERA_COLOURS[s % 8], label=name)
    ax.set_title(f"Each corner's error, × {scale:g} (0.1 px = {0.1 * scale:g} px arrow)",
                 fontsize=10)
    ax.legend(loc="lower left", fontsize=7, ncol=3, bbox_to_anchor=(0, -0.02))
    nx, ny = 6, 4
    ix = np.clip((uv[:, 0] / W * nx).astype(int), 0, nx - 1)
    iy = np.clip((uv[:, 1] / H * ny).astype(int), 0, ny - 1)
    centres, means, counts = [], [], []
    for i in range(nx):
        for j in range(ny):
            m = (ix == i) & (iy == j)
            if m.sum() >= 3:
                centres.append(((i + 0.5) * W / nx, (j + 0.5) * H / ny))
                means.append(d[m].mean(axis=0))
                counts.append(int(m.sum()))
    if centres:
        c, mu = np.array(centres), np.array(means)
        bx.quiver(c[:, 0], c[:, 1], mu[:, 0], mu[:, 1], angles="xy", scale_units="xy",
                  scale=1 / (10 * scale), width=0.006, color="k")
        for (x, y), n, m in zip(c, counts, mu, strict=True):
            bx.text(x, y + 0.09 * H, f"n={n}\n({m[0]:+.3f}, {m[1]:+.3f})", ha="center",
                    fontsize=6.5, color="0.3")
    bx.set_title(f"Mean error per image cell, × {10 * scale:g} (0.01 px = {0.1 * scale:g} px)",
                 fontsize=10)
    for a in (ax, bx):
        a.plot([0, W, W, 0, 0], [0, 0, H, H, 0], "k-", lw=0.8)
        a.set_xlim(-0.05 * W, 1.05 * W)
        a.set_ylim(1.08 * H, -0.05 * H)
        a.set_aspect("equal")
        a.set_xlabel("u (px)")
        a.set_ylabel("v (px)")
    return save(fig, path)


def error_histograms(path: Path, errors: dict[str, np.ndarray], baseline: np.ndarray) -> Path:
    """Histograms of dx, dy, dr for the renders, with the detector baseline overlaid."""
    fig = figure(12, 3.8)
    lim = max(0.05, float(np.quantile(np.abs(np.concatenate(list(errors.values()))), 0.995)))
    bins = np.linspace(-lim, lim, 51)
    for k, (name, e) in enumerate(errors.items()):
        ax = fig.add_subplot(1, len(errors), k + 1)
        ax.hist(e, bins=bins, density=True, alpha=0.6, color="tab:blue",
                label=f"rendered: mean {e.mean():+.4f}, std {e.std(ddof=1):.4f}")
        if name in ("dx", "dy"):
            b = baseline[:, 0 if name == "dx" else 1]
            ax.hist(b, bins=bins, density=True, histtype="step", lw=1.5, color="k",
                    label=f"detector on exact images: std {b.std(ddof=1):.4f}")
        ax.set_xlabel(f"{name} (px)")
        ax.set_ylabel("density")
        ax.legend(fontsize=7, loc="upper left")
    return save(fig, path)


def error_against(path: Path, panels: list[tuple[str, np.ndarray, str, np.ndarray]]) -> Path:
    """Scatter of errors against variables with binned means ± 95 % intervals."""
    fig = figure(4 * len(panels), 3.6)
    for k, (xlabel, x, ylabel, y) in enumerate(panels):
        ax = fig.add_subplot(1, len(panels), k + 1)
        ax.plot(x, y, ".", ms=2, alpha=0.3, color="tab:blue")
        edges = np.quantile(x, np.linspace(0, 1, 9))
        idx = np.clip(np.searchsorted(edges, x, side="right") - 1, 0, 7)
        centres, means, half = [], [], []
        for b in range(8):
            yy = y[idx == b]
            if len(yy) > 2:
                centres.append(np.median(x[idx == b]))
                means.append(yy.mean())
                half.append(1.96 * yy.std(ddof=1) / np.sqrt(len(yy)))
        ax.errorbar(centres, means, yerr=half, fmt="o-", color="k", ms=4, capsize=3,
                    label="mean per bin ± 95 %")
        ax.axhline(0, color="tab:red", lw=0.8)
        lim = max(0.05, float(np.quantile(np.abs(y), 0.99)))
        ax.set_ylim(-lim, lim)
        ax.set_xlabel(xlabel)
        ax.set_ylabel(ylabel)
        ax.legend(fontsize=7)
    return save(fig, path)


# ---------------------------------------------------------------------- PSF / texture
def pixel_grids(path: Path, images: list[tuple[str, np.ndarray]], centre: tuple[int, int],
                half: int = 3, per_row: int = 3) -> Path:
    """Enlarged (2·half + 1)² pixel neighbourhoods with their values printed; brightness is
    value^0.25 so that small leaks show."""
    rows = -(-len(images) // per_row)
    fig = figure(4.6 * per_row, 4.4 * rows)
    i0, j0 = centre
    for k, (title, img) in enumerate(images):
        ax = fig.add_subplot(rows, per_row, k + 1)
        patch = img[j0 - half:j0 + half + 1, i0 - half:i0 + half + 1]
        ax.imshow(np.clip(patch, 0, 1) ** 0.25, cmap="gray", vmin=0, vmax=1,
                  interpolation="nearest",
                  extent=(i0 - half, i0 + half + 1, j0 + half + 1, j0 - half))
        for jj in range(patch.shape[0]):
            for ii in range(patch.shape[1]):
                v = patch[jj, ii]
                ax.text(i0 - half + ii + 0.5, j0 - half + jj + 0.5, "0" if v == 0 else f"{v:.3g}",
                        ha="center", va="center", fontsize=8,
                        color="k" if v > 0.1 else ("tab:orange" if v > 0 else "0.6"))
        ax.set_title(title, fontsize=10)
        ax.set_xlabel("u (px)")
        ax.set_ylabel("v (px)")
    return save(fig, path)


def texture_views(path: Path, images: list[tuple[str, np.ndarray]], edges_u: np.ndarray,
                  edges_v: np.ndarray) -> Path:
    """Rendered texture views with the projected texel edges drawn over them."""
    fig = figure(5.2 * len(images), 4.4)
    for k, (title, img) in enumerate(images):
        ax = fig.add_subplot(1, len(images), k + 1)
        H, W = img.shape
        ax.imshow(img, cmap="gray", vmin=0, vmax=255, interpolation="nearest",
                  extent=(0, W, H, 0))
        for u in edges_u:
            ax.axvline(u, color="tab:red", lw=0.8, ls="--")
        for v in edges_v:
            ax.axhline(v, color="tab:red", lw=0.8, ls="--")
        ax.set_title(title, fontsize=9)
    return save(fig, path)


def profile(path: Path, rows: list[tuple[str, np.ndarray]], edges: np.ndarray, x0: int,
            title: str) -> Path:
    """Pixel values along one image row near texel edges (dashed: projected edges)."""
    fig = figure(9, 3.9)
    ax = fig.add_subplot()
    for name, values in rows:
        x = x0 + np.arange(len(values)) + 0.5
        ax.step(x, values, where="mid", label=name)
    for e in edges:
        if x0 <= e <= x0 + len(rows[0][1]):
            ax.axvline(e, color="tab:red", ls="--", lw=0.8)
    ax.set_xlabel("u (px); dashed: texel edges projected by the camera model")
    ax.set_ylabel("pixel value (8-bit)")
    ax.set_title(title)
    ax.legend(fontsize=8, loc="upper center", bbox_to_anchor=(0.5, -0.22), ncol=3)
    return save(fig, path)
