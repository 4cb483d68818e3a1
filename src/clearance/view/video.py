"""The viewer's scene as a video for talks: `render_video(scene_or_path, out)`,
`clearance animate RESULT.nc -o FILE.mp4|.gif`.

Drawn with matplotlib's Agg canvas (no window, no display needed) from the same Scene and
shapes as the HTML viewer: the mechanism in 3-D (the ideal run as a grey ghost), a time
stamp, and one inset per clearance joint with the ball centre in units of the clearance,
its trace and the contact-force arrow coloured by magnitude. MP4 (H.264) is encoded by the
ffmpeg that ships inside the imageio-ffmpeg wheel; GIF by Pillow. Video time runs at
`speed` x simulated time (default: the whole run in 20 s of video).
"""

from __future__ import annotations

import os
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from clearance.io.files import atomic_path
from clearance.model.bodies import rotation_matrices
from clearance.view.scene import Scene, SceneError, load_scene

__all__ = ["VideoInfo", "render_video", "video_times"]

FORMATS = (".mp4", ".gif")
MAX_VIDEO_FRAMES = 20_000  # 13 min at 25 fps
MAX_INSETS = 6  # close-ups in a video frame (the first joints')


@dataclass(frozen=True)
class VideoInfo:
    """What was written: path, frames, fps, size (width, height), speed, the simulated
    time of each video frame and the scene frame it shows."""

    path: Path
    frames: int
    fps: float
    size: tuple
    speed: float
    times: np.ndarray
    scene_frames: np.ndarray

    @property
    def duration(self) -> float:
        return self.frames / self.fps


def _frame_count(t0: float, t1: float, fps: float, speed: float) -> int:
    return max(int(np.floor((t1 - t0) / (speed / fps) * (1 + 1e-12))) + 1, 1)


def video_times(t0: float, t1: float, fps: float, speed: float) -> np.ndarray:
    """Simulated times of the video frames: t0 + k speed / fps up to t1 (inclusive)."""
    return t0 + speed / fps * np.arange(_frame_count(t0, t1, fps, speed))


def _world(poses: np.ndarray, k: int, b: int, pts: np.ndarray) -> np.ndarray:
    p = poses[k, b].astype(float)
    return p[:3] + pts @ rotation_matrices(p[3:]).T


class _Drawing:
    """The figure and its artists, created once and updated per frame."""

    def __init__(self, scene: Scene, size: tuple, dpi: float, ghost: bool):
        from matplotlib.backends.backend_agg import FigureCanvasAgg
        from matplotlib.figure import Figure
        from mpl_toolkits.mplot3d.art3d import Poly3DCollection

        self.scene = scene
        w, h = size
        self.fig = Figure(figsize=(w / dpi, h / dpi), dpi=dpi, facecolor="white")
        self.canvas = FigureCanvasAgg(self.fig)
        ncl = min(len(scene.clearances), MAX_INSETS)
        main_w = 0.70 if ncl else 1.0
        ax = self.fig.add_axes((0.0, 0.0, main_w, 0.94), projection="3d")
        self.ax = ax
        self.runs = [k for k in range(len(scene.runs)) if ghost or k == len(scene.runs) - 1]
        self.items: list = []  # (run, body index, kind, artist, body-frame points)
        px_per_m = 0.55 * h / scene.size
        for r in self.runs:
            is_ghost = r != len(scene.runs) - 1
            for b, name in enumerate(scene.bodies):
                for prim in scene.shapes.get(name, []) + scene.glyphs.get(name, []):
                    colour = "#b0b8c0" if is_ghost else prim["colour"]
                    alpha = 0.45 if is_ghost else 1.0
                    if prim["type"] == "rod":
                        pts = np.array([prim["a"], prim["b"]])
                        lw = max(1.0, 2 * prim["radius"] * px_per_m * 72 / dpi)
                        (art,) = ax.plot(
                            *pts.T, color=colour, lw=lw, alpha=alpha, solid_capstyle="round"
                        )
                        self.items.append((r, b, "line", art, pts))
                    elif prim["type"] == "sphere":
                        pts = np.array([prim["centre"]])
                        ms = max(2.0, 2 * prim["radius"] * px_per_m * 72 / dpi)
                        (art,) = ax.plot(*pts.T, "o", color=colour, ms=ms, alpha=alpha)
                        self.items.append((r, b, "line", art, pts))
                    elif prim["type"] == "mesh":
                        v = np.array(prim["vertices"])
                        ring = v[: len(v) // 2]  # the top face of the prism
                        art = Poly3DCollection(
                            [ring],
                            facecolor=colour,
                            edgecolor="#2c3e50",
                            alpha=0.35 if is_ghost else 0.85,
                        )
                        ax.add_collection3d(art)
                        self.items.append((r, b, "poly", art, ring))
        for prim in scene.glyphs.get(scene.geometry.get("ground", "ground"), []):
            pts = np.array([prim["a"], prim["b"]] if prim["type"] == "rod" else [prim["centre"]])
            ax.plot(*pts.T, "o-", color="#2c3e50", ms=3, lw=2)
        self._limits()
        ax.set_xlabel("x [m]", fontsize=8)
        ax.set_ylabel("y [m]", fontsize=8)
        ax.set_zlabel("z [m]", fontsize=8)
        ax.tick_params(labelsize=7)
        ax.view_init(elev=22, azim=-60)
        self.stamp = self.fig.text(0.01, 0.965, "", fontsize=12, family="monospace")
        self.fig.text(0.99, 0.965, scene.title, fontsize=10, ha="right", color="#34495e")
        shown = scene.clearances[:MAX_INSETS]
        self.insets = [self._inset(c, k, ncl, main_w) for k, c in enumerate(shown)]
        if len(scene.clearances) > MAX_INSETS:
            self.fig.text(
                0.99,
                0.01,
                f"close-ups of the first {MAX_INSETS} of {len(scene.clearances)} clearance joints",
                ha="right",
                fontsize=8,
            )

    def _limits(self):
        sc = self.scene
        P = sc.runs[-1].poses[:, :, :3].reshape(-1, 3)
        lo, hi = P.min(axis=0) - 0.3 * sc.size, P.max(axis=0) + 0.3 * sc.size
        lo[2] = min(lo[2], 0.0)
        mid, half = 0.5 * (lo + hi), 0.5 * float(np.max(hi - lo))
        for setter, m in zip(
            (self.ax.set_xlim, self.ax.set_ylim, self.ax.set_zlim), mid, strict=True
        ):
            setter(m - half, m + half)
        self.ax.set_box_aspect((1, 1, 1))

    def _inset(self, c, k, n, left):
        from matplotlib.colors import Normalize

        gap = 0.08 if n <= 2 else 0.05
        hgt = min(0.4, (0.92 - gap * (n - 1)) / max(n, 1))  # (n <= MAX_INSETS: > 0.1)
        y0 = 0.92 - (k + 1) * hgt - k * gap
        ax = self.fig.add_axes((left + 0.05, y0, 0.26, hgt))
        e = c.e / c.info["c"]
        x = e - e.mean(axis=0)
        spherical = c.info["kind"] == "spherical"
        if spherical and np.any(np.abs(x) > 0):  # the plane of the trace's main directions
            _, _, vt = np.linalg.svd(x, full_matrices=False)
            U = vt[:2]
        else:  # journals, sliders: the bearing plane, the guide's cross-section (f, g)
            U = np.eye(3)[:2]
        u = e @ U.T
        if c.info["kind"] == "prismatic":
            hh = c.info.get("height_clearance", c.info["c"]) / c.info["c"]
            ax.plot([-1, 1, 1, -1, -1], [-hh, -hh, hh, hh, -hh], color="#7f8c8d", lw=1.0)
        else:
            a = np.linspace(0, 2 * np.pi, 200)
            ax.plot(np.cos(a), np.sin(a), color="#7f8c8d", lw=1.0)
        ax.plot([0], [0], "+", color="#7f8c8d")
        (trace,) = ax.plot([], [], color="#2471a3", lw=0.8)
        (dot,) = ax.plot([], [], "o", color="#d35400", ms=6)
        quiv = ax.quiver(
            [0], [0], [0], [0], angles="xy", scale_units="xy", scale=1.0, width=0.02, color="red"
        )
        ax.set_xlim(-1.35, 1.35)
        ax.set_ylim(-1.35, 1.35)
        ax.set_aspect("equal")
        ax.tick_params(labelsize=7)
        ax.set_title(f"{c.info['name']}: ball centre / c, in the plane of its trace", fontsize=8)
        from matplotlib import colormaps

        return dict(
            track=c,
            U=U,
            u=u,
            trace=trace,
            dot=dot,
            quiver=quiv,
            ax=ax,
            cmap=colormaps["plasma"],
            norm=Normalize(0, c.peak or 1.0),
        )

    def draw(self, k: int, t: float) -> np.ndarray:
        sc = self.scene
        for r, b, kind, art, pts in self.items:
            w = _world(sc.runs[r].poses, k, b, pts)
            if kind == "line":
                art.set_data_3d(w[:, 0], w[:, 1], w[:, 2])
            else:
                art.set_verts([w])
        self.stamp.set_text(f"t = {t:8.4f} s")
        for ins in self.insets:
            c, u = ins["track"], ins["u"]
            ins["trace"].set_data(u[: k + 1, 0], u[: k + 1, 1])
            ins["dot"].set_data([u[k, 0]], [u[k, 1]])
            q = ins["quiver"]
            if c.contact[k] and c.fn[k] > 0:
                f = c.force[k] @ ins["U"].T
                f = f / (np.linalg.norm(f) or 1.0) * (0.3 + 0.9 * min(c.fn[k] / (c.peak or 1), 1))
                q.set_offsets([[u[k, 0] - f[0], u[k, 1] - f[1]]])
                q.set_UVC([f[0]], [f[1]])
                q.set_color(ins["cmap"](ins["norm"](c.fn[k])))
                q.set_visible(True)
            else:
                q.set_visible(False)
        self.canvas.draw()
        buf = np.asarray(self.canvas.buffer_rgba())
        return np.ascontiguousarray(buf[:, :, :3])


def render_video(
    scene: Scene | str | os.PathLike,
    out: str | os.PathLike | None = None,
    *,
    fps: float = 25.0,
    speed: float | None = None,
    size: tuple[int, int] | None = None,
    dpi: float = 100.0,
    ghost: bool = True,
    progress=None,
    **load,
) -> VideoInfo:
    """Write the video of a Scene (or of a result file: `load_scene(**load)`) to `out`
    (.mp4 or .gif; default: the result's name with .mp4), atomically.

    fps: frames per second of video; speed: simulated seconds per video second (default:
    the whole run in 20 s of video, 0.1 for the default 2 s run); size: (width, height) in
    pixels, even (default 1280 x 720 for MP4, 800 x 450 for GIF); ghost: draw the ideal run;
    progress: called with (frame, frames) after each frame.
    """
    if not isinstance(scene, Scene):
        scene = load_scene(scene, **load)
    out = Path(out) if out is not None else Path(scene.source).with_suffix(".mp4")
    ext = out.suffix.lower()
    if ext not in FORMATS:
        raise SceneError(f"{out}: unknown video format {ext!r}; allowed: {', '.join(FORMATS)}")
    if not (np.isfinite(fps) and fps > 0):
        raise SceneError(f"fps = {fps}: expected a positive number")
    t0, t1 = float(scene.time[0]), float(scene.time[-1])
    if speed is None:  # the whole run in 20 s of video
        speed = (t1 - t0) / 20.0 if t1 > t0 else 0.1
    if not (np.isfinite(speed) and speed > 0):
        raise SceneError(f"speed = {speed}: expected a positive number")
    if size is None:
        size = (1280, 720) if ext == ".mp4" else (800, 450)
    w, h = (int(x) for x in size)
    if w < 64 or h < 64 or w % 2 or h % 2:
        raise SceneError(f"size = {w}x{h}: expected even numbers of pixels, at least 64")
    nframes = _frame_count(t0, t1, fps, speed)
    if nframes > MAX_VIDEO_FRAMES:
        raise SceneError(
            f"speed = {speed:g} at {fps:g} fps makes {nframes} frames for {t1 - t0:g} s of "
            f"motion; at most {MAX_VIDEO_FRAMES} (raise --speed or lower --fps)"
        )
    times = video_times(t0, t1, fps, speed)
    frames = np.clip(np.searchsorted(scene.time, times, side="right") - 1, 0, scene.time.size - 1)
    drawing = _Drawing(scene, (w, h), dpi, ghost)
    with atomic_path(out) as tmp:
        if ext == ".mp4":
            _mp4(tmp, drawing, times, frames, fps, (w, h), progress)
        else:
            _gif(tmp, drawing, times, frames, fps, progress)
    return VideoInfo(out, len(times), float(fps), (w, h), float(speed), times, frames)


def _mp4(tmp: Path, drawing, times, frames, fps, size, progress):
    import imageio_ffmpeg

    writer = imageio_ffmpeg.write_frames(
        str(tmp),
        size,
        fps=fps,
        codec="libx264",
        macro_block_size=1,
        output_params=["-f", "mp4"],
        ffmpeg_log_level="error",
    )
    writer.send(None)
    try:
        for i, (t, k) in enumerate(zip(times, frames, strict=True)):
            img = drawing.draw(int(k), float(t))
            if img.shape[1] != size[0] or img.shape[0] != size[1]:
                raise SceneError(f"rendered {img.shape[1]}x{img.shape[0]}, expected {size}")
            writer.send(img.tobytes())
            if progress is not None:
                progress(i + 1, len(times))
    finally:
        writer.close()


def _gif(tmp: Path, drawing, times, frames, fps, progress):
    from PIL import Image

    images = []
    for i, (t, k) in enumerate(zip(times, frames, strict=True)):
        img = Image.fromarray(drawing.draw(int(k), float(t)))
        images.append(img.convert("P", palette=Image.Palette.ADAPTIVE, colors=128))
        if progress is not None:
            progress(i + 1, len(times))
    images[0].save(
        tmp,
        format="GIF",
        save_all=True,
        append_images=images[1:],
        duration=int(round(1000 / fps)),
        loop=0,
    )
