"""frame_regions.py OUTDIR NAME...: each frame of ours (OUTDIR/NAME.pfm, its world
positions NAME.pos.pfm and coverage NAME.mask.pfm, from tests/web/render_frame.mjs)
against Cycles' (OUTDIR/cycles.pfm), region by region, on the scene and view of
OUTDIR/frame.json (the room's regions, or for a world without moving spheres the
sun and its shadow). Prints a markdown table (bias: our light over Cycles' in the
region; RMSE over its pixels, relative to Cycles' mean there, and over 4 x 4
blocks wholly in it, where the path tracer's own noise is a quarter), writes
OUTDIR/frame_vs_cycles.csv and, a picture a frame, OUTDIR/frame_NAME.png (ours,
Cycles', and |ours - Cycles| / Cycles from 0 black to 0.5 white). Runs under
Debian's python3 (numpy).
"""
import json
import os
import subprocess
import sys

import numpy as np


def read_pfm(path):
    with open(path, "rb") as f:
        kind = f.readline().strip()
        w, h = (int(v) for v in f.readline().split())
        scale = float(f.readline())
        data = np.frombuffer(f.read(), dtype="<f4" if scale < 0 else ">f4")
    return data.reshape(h, w, 3 if kind == b"PF" else 1)


def regions(scene, pos, mask, out, truth):
    """Boolean masks, one a region, from the world position under each pixel (the room), or
    from Cycles' direct light rendered apart (OUTDIR/cycles_direct.pfm, a scene without
    moving spheres: the sun and its shadow)."""
    surface = mask[..., 0] > 0.5
    if not scene.get("spheres"):
        direct = read_pfm(os.path.join(out, "cycles_direct.pfm")).mean(-1)
        shadow = surface & (direct < 0.02 * truth.mean(-1))
        # Two pixels off every shadow edge: a shadow map's edge is not a path tracer's.
        return [("every surface pixel", surface), ("in the sun", erode(surface & ~shadow)),
                ("in its shadow", erode(shadow))]
    s = scene["spheres"][0]
    c, r = np.array(s["center"]), s["radius"]
    lamp = np.array(scene["lamps"][0]["position"])
    sphere = surface & (np.linalg.norm(pos - c, axis=-1) < r + 0.01)
    static = surface & ~sphere
    floor = static & (np.abs(pos[..., 1]) < 0.005)
    # In the sphere's shadow: the segment to the lamp passes within r of its centre.
    d = lamp - pos
    dd = np.einsum("...k,...k->...", d, d)
    t = np.clip(np.einsum("...k,...k->...", c - pos, d) / np.maximum(dd, 1e-12), 0, 1)
    gap = np.linalg.norm(pos + t[..., None] * d - c, axis=-1)
    shadow = floor & (gap < r)
    contact = floor & ~shadow & (np.hypot(pos[..., 0] - c[0], pos[..., 2] - c[2]) < 0.35)
    lo, hi = np.array([0.0, 0.0, 0.0]), np.array([6.0, 3.0, 4.0])
    near = (np.abs(pos - lo) < 0.25).sum(-1) + (np.abs(pos - hi) < 0.25).sum(-1)
    corners = static & (near >= 2)
    window = static & (np.linalg.norm(pos - np.array([3.0, 1.6, 0.0]), axis=-1) < 1.0)
    open_floor = floor & ~shadow & ~contact & ~corners & ~window
    return [("all static pixels", static), ("open floor", open_floor), ("moving sphere", sphere),
            ("its lamp shadow", shadow), ("its contact (0.35 m)", contact), ("corners", corners),
            ("near the window", window)]


def erode(m, r=2):
    """m where every pixel within r (a square) is in m too."""
    p = np.pad(m, r, constant_values=False)
    out = m.copy()
    for dy in range(2 * r + 1):
        for dx in range(2 * r + 1):
            out &= p[dy:dy + m.shape[0], dx:dx + m.shape[1]]
    return out


def blocks(a, k=4):
    """The means of a's k x k blocks."""
    h, w = a.shape[0] // k * k, a.shape[1] // k * k
    return a[:h, :w].reshape(h // k, k, w // k, k).mean((1, 3))


def srgb8(img):
    """Linear radiance, scaled to show, as 8-bit sRGB."""
    v = np.clip(img, 0.0, 1.0)
    v = np.where(v <= 0.0031308, 12.92 * v, 1.055 * np.power(v, 1 / 2.4) - 0.055)
    return (v * 255.0 + 0.5).astype(np.uint8)


def picture(out, name, ours, truth):
    """Ours, Cycles', and the relative error (0 black, 0.5 white), side by side, as a .png."""
    err = np.abs(ours - truth).mean(-1, keepdims=True) / np.maximum(truth.mean(-1, keepdims=True), 1e-4)
    gap = np.zeros((ours.shape[0], 4, 3), np.uint8)
    row = np.concatenate([srgb8(ours * 0.6), gap, srgb8(truth * 0.6), gap,
                          srgb8(np.repeat(np.clip(err * 2.0, 0, 1), 3, axis=-1))], axis=1)[::-1]
    ppm = os.path.join(out, "frame_%s.ppm" % name)
    with open(ppm, "wb") as f:
        f.write(b"P6\n%d %d\n255\n" % (row.shape[1], row.shape[0]))
        f.write(row.tobytes())
    subprocess.run(["oiiotool", ppm, "-o", os.path.join(out, "frame_%s.png" % name)], check=True)
    os.remove(ppm)


def main():
    out, names = sys.argv[1], sys.argv[2:]
    scene = json.load(open(os.path.join(out, "frame.json")))
    truth = read_pfm(os.path.join(out, "cycles.pfm"))
    rows = ["frame,region,pixels,bias,rmse_rel,rmse_rel_blocks"]
    for name in names:
        ours = read_pfm(os.path.join(out, name + ".pfm"))
        pos = read_pfm(os.path.join(out, name + ".pos.pfm"))
        mask = read_pfm(os.path.join(out, name + ".mask.pfm"))
        print("\n%s against Cycles (64 bounces):\n" % name)
        print("| region | pixels | bias | RMSE | RMSE, 4 x 4 blocks |")
        print("|---|---:|---:|---:|---:|")
        lo, lt = ours.mean(-1), truth.mean(-1)
        for label, m in regions(scene, pos, mask, out, truth):
            n = int(m.sum())
            if n == 0:
                continue
            bias = lo[m].sum() / lt[m].sum()
            rmse = np.sqrt(np.mean((lo[m] - lt[m]) ** 2)) / lt[m].mean()
            whole = blocks(m.astype(float)) > 0.999
            bo, bt = blocks(lo)[whole], blocks(lt)[whole]
            brmse = np.sqrt(np.mean((bo - bt) ** 2)) / bt.mean() if whole.any() else float("nan")
            print("| %s | %d | %.3f | %.1f %% | %.1f %% |" % (label, n, bias, 100 * rmse, 100 * brmse))
            rows.append("%s,%s,%d,%.4f,%.4f,%.4f" % (name, label, n, bias, rmse, brmse))
        picture(out, name, ours, truth)
    open(os.path.join(out, "frame_vs_cycles.csv"), "w").write("\n".join(rows) + "\n")


main()
