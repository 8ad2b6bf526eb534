"""The runout as a movie: runout.mp4 and a small runout.gif, drawn by figures.py --animate.

Every saved frame of results.h5 becomes one picture (the particles coloured by their
displacement, the time, the initial outlines, the deposit front and the final deposit tip),
piped as raw RGBA into one ffmpeg, which encodes both files. Matplotlib draws the axes, labels
and colour bar once; each frame then paints the particles into a copy of that picture with
numpy and draws only the few lines and the time over them, so that the movie costs less than
the figures (docs/postproc.md).
"""
import os
import shutil
import subprocess

import h5py
import numpy as np

AXES_WIDTH, AXES_HEIGHT = 800, 440       # pixels: the largest plot of the particles
LEFT, RIGHT, BOTTOM, TOP = 70, 100, 45, 60  # pixels around it: labels, colour bar, time and legend
MIN_WIDTH = 600
DPI = 100
GIF_WIDTH = 480                     # pixels; the GIF is for documents, small


def ffmpeg_command(ffmpeg, size, fps, mp4, gif):
    # One input, two outputs: H.264 for sharing, and a GIF with its own 64-colour palette. The
    # last picture is held for a second (tpad) so that the deposit can be seen.
    graph = ("[0:v]tpad=stop_mode=clone:stop_duration=1,split=2[movie][small];"
             "[small]scale='min(%d,iw)':-2:flags=fast_bilinear,split[a][b];"
             "[a]palettegen=max_colors=64[palette];"
             "[b][palette]paletteuse=dither=none[gif]" % GIF_WIDTH)
    return [ffmpeg, "-loglevel", "error", "-y", "-f", "rawvideo", "-pix_fmt", "rgba",
            "-s", "%dx%d" % size, "-r", "%g" % fps, "-i", "-", "-filter_complex", graph,
            "-map", "[movie]", "-c:v", "libx264", "-preset", "ultrafast", "-crf", "26", "-pix_fmt", "yuv420p",
            "-movflags", "+faststart", "-f", "mp4", mp4,
            "-map", "[gif]", "-f", "gif", gif]


def frames_per_second(time):
    # Real time where the frames allow it, within 5 to 25 pictures a second.
    span = time[-1] - time[0]
    if len(time) < 2 or span <= 0:
        return 5.0
    return float(min(25.0, max(5.0, round((len(time) - 1) / span))))


def animate(results, metrics, out, written, front=None):
    """Writes OUT/runout.mp4 and OUT/runout.gif; returns False (and writes nothing) without ffmpeg."""
    import matplotlib.pyplot as plt

    ffmpeg = shutil.which("ffmpeg")
    if ffmpeg is None:
        print("note: no animation: ffmpeg is not installed (apt-get install ffmpeg)")
        return False
    with h5py.File(results, "r") as f:
        x0 = f["particles/initial_position"][...]
        volume = f["particles/volume"][...]
        x = f["frames/position"][...]
        time = f["frames/time"][...]
        names = [n.decode() if isinstance(n, bytes) else n for n in f["bodies/names"][...]]
        outlines = []
        for name in names:
            group = f["bodies/" + name]
            outlines += [group["loop_%d" % k][...] for k in range(int(group.attrs["loops"]))]
    moved = np.linalg.norm(x - x0[None, :, :], axis=2)

    everything = np.vstack([x.reshape(-1, 2)] + outlines)
    lo, hi = everything.min(axis=0), everything.max(axis=0)
    pad = 0.04 * (hi - lo).max()
    lo, hi = lo - pad, hi + pad
    # Pixels: the plot fits AXES_WIDTH x AXES_HEIGHT at the material's aspect ratio, with margins
    # for the axis labels, the legend above and the colour bar to the right.
    scale = min(AXES_WIDTH / (hi[0] - lo[0]), AXES_HEIGHT / (hi[1] - lo[1]))  # pixels per metre
    plot_width, plot_height = (hi - lo) * scale
    width = 2 * int(np.ceil(max(LEFT + plot_width + RIGHT, MIN_WIDTH) / 2))  # even, as H.264 wants
    height = 2 * int(np.ceil((BOTTOM + plot_height + TOP) / 2))
    left = LEFT + (width - LEFT - plot_width - RIGHT) / 2  # a narrow plot is centred
    fig = plt.figure(figsize=((width + 0.5) / DPI, (height + 0.5) / DPI), dpi=DPI)  # not a pixel short
    ax = fig.add_axes([left / width, BOTTOM / height, plot_width / width, plot_height / height])
    colour_axes = fig.add_axes([(left + plot_width + 12) / width, BOTTOM / height, 12 / width, plot_height / height])
    ax.set_xlim(lo[0], hi[0])
    ax.set_ylim(lo[1], hi[1])
    # The particles are painted straight into the picture, squares of the particle spacing
    # (sqrt(volume)) so that neighbours touch: drawing 6000 markers with matplotlib 40 times
    # would cost more than all the figures. The rest is drawn once (the background), and the
    # lines, markers and time over the particles each frame.
    side = max(1, int(round(1.5 * np.sqrt(np.median(volume)) * scale)))  # seeded in triangles: not a grid
    colours = (plt.get_cmap("viridis")(np.linspace(0, 1, 256)) * 255).astype(np.uint8).view(np.uint32).ravel()
    vmax = max(float(moved.max()), 1e-9)
    fig.colorbar(plt.cm.ScalarMappable(norm=plt.Normalize(0.0, vmax), cmap="viridis"), cax=colour_axes,
                 label="displacement (m)")
    overlay = []  # drawn over the particles in every frame
    for k, loop in enumerate(outlines):
        closed = np.vstack([loop, loop[:1]])
        overlay += ax.plot(closed[:, 0], closed[:, 1], "k--", lw=0.7, label="initial outline" if k == 0 else None)
    tip = metrics.get("deposit_tip_m")
    if tip and metrics.get("deposit_found"):
        overlay += ax.plot(*tip, "rv", ms=7, label="deposit tip at rest (runout %.2f m)" % metrics["runout_distance_m"])
    front_line = None
    if front is not None and len(front["time_s"]) == len(time):
        front_line = ax.axvline(front["front_x_m"][0], color="r", ls=":", lw=1.0, label="front")
        overlay.append(front_line)
    ax.set_xlabel("x (m)")
    ax.set_ylabel("y (m)")
    fig.legend(loc="upper right", bbox_to_anchor=(1.0, 1.0 - 26 / height), ncol=3, fontsize=8, frameon=False)
    stamp = fig.text(8 / width, 1.0 - 8 / height, "", va="top", fontsize=11)
    overlay.append(stamp)
    scene = metrics.get("scene", "")
    for artist in overlay:
        artist.set_visible(False)
    fig.canvas.draw()
    background = fig.canvas.copy_from_bbox(fig.bbox)
    height, width = np.asarray(fig.canvas.buffer_rgba()).shape[:2]  # as drawn (inches round)
    for artist in overlay:
        artist.set_visible(True)
    # Pixel rows and columns of the axes box, and of every particle (a square's top left corner).
    box = ax.get_window_extent()
    row_range = (int(np.ceil(height - box.y1)), int(np.floor(height - box.y0)))
    column_range = (int(np.ceil(box.x0)), int(np.floor(box.x1)))
    square = (np.arange(side)[:, None] * width + np.arange(side)[None, :]).ravel()  # offsets in the picture

    mp4, gif = os.path.join(out, "runout.mp4"), os.path.join(out, "runout.gif")
    temporary = [mp4 + ".tmp", gif + ".tmp"]  # renamed when both are whole
    command = ffmpeg_command(ffmpeg, (width, height), frames_per_second(time), *temporary)
    encoder = subprocess.Popen(command, stdin=subprocess.PIPE, stderr=subprocess.PIPE)
    try:
        for k in range(len(time)):
            fig.canvas.restore_region(background)
            picture = np.asarray(fig.canvas.buffer_rgba())
            pixels = picture.view(np.uint32).reshape(-1)  # one RGBA pixel per element
            corner = ax.transData.transform(x[k]) - side / 2
            columns = np.clip(np.round(corner[:, 0]).astype(int), column_range[0], column_range[1] - side + 1)
            rows = np.clip(np.round(height - side - corner[:, 1]).astype(int), row_range[0], row_range[1] - side + 1)
            colour = colours[np.clip((moved[k] / vmax * 255).astype(int), 0, 255)]
            pixels[((rows * width + columns)[:, None] + square[None, :]).ravel()] = np.repeat(colour, side * side)
            stamp.set_text("%s   t = %.2f s" % (scene, time[k]))
            if front_line is not None:
                front_line.set_xdata([front["front_x_m"][k]] * 2)
            for artist in overlay:
                (ax if artist is not stamp else fig).draw_artist(artist)
            try:
                encoder.stdin.write(picture.tobytes())
            except BrokenPipeError:  # ffmpeg stopped: its message follows
                break
        try:
            encoder.stdin.close()
        except BrokenPipeError:
            pass
        error = encoder.stderr.read().decode(errors="replace").strip()
        if encoder.wait() != 0:
            raise RuntimeError("ffmpeg failed: " + (error.splitlines() or ["no message"])[-1])
        for path, final in zip(temporary, (mp4, gif)):
            os.replace(path, final)
            written.append(final)
    finally:
        plt.close(fig)
        if encoder.poll() is None:
            encoder.kill()
            encoder.wait()
        for path in temporary:
            if os.path.exists(path):
                os.remove(path)
    return True
