"""Analytic scans built with numpy alone, where every answer is known: one head at the origin,
1.6 m above a ground plane, in a room of walls (x = 40 m ahead, y = +-25 m), with one box face
at x = 15 m moving at a known velocity. Doppler by Eq. 6: v = e . (V_point - V_ego)."""

import numpy as np

GROUND_Z = -1.6
OBJECT_X = 15.0
OBJECT_HALF_WIDTH = 1.0


def beam_directions(rows, cols, fov_h_deg, fov_v_deg):
    """Unit beams through pixel centres, column 0 left (+azimuth), row 0 top: (rows, cols, 3)."""
    res_h, res_v = fov_h_deg / cols, fov_v_deg / rows
    az = np.deg2rad(fov_h_deg / 2 - (np.arange(cols) + 0.5) * res_h)
    el = np.deg2rad(fov_v_deg / 2 - (np.arange(rows) + 0.5) * res_v)
    A, E = np.meshgrid(az, el)
    return np.stack([np.cos(E) * np.cos(A), np.cos(E) * np.sin(A), np.sin(E)], axis=-1)


def room_scan(ego=(6.0, 0.4, 0.0), obj=(-2.0, 3.0, 0.0), rows=48, cols=160, fov_h=80.0, fov_v=24.0,
              noise=0.01, seed=1):
    """Returns dict: x, y, z, v (rows, cols) float32, moving (rows, cols) bool, ego, obj."""
    d = beam_directions(rows, cols, fov_h, fov_v)
    dx, dy, dz = d[..., 0], d[..., 1], d[..., 2]
    with np.errstate(divide="ignore", invalid="ignore"):
        candidates = [
            np.where(dz < 0, GROUND_Z / dz, np.inf),
            np.where(dx > 0, 40.0 / dx, np.inf),
            np.where(dy > 0, 25.0 / dy, np.inf),
            np.where(dy < 0, -25.0 / dy, np.inf),
        ]
        t = np.min(candidates, axis=0)
        t_obj = np.where(dx > 0, OBJECT_X / dx, np.inf)
    hit = d * t_obj[..., None]
    moving = (t_obj < t) & (np.abs(hit[..., 1]) <= OBJECT_HALF_WIDTH) & (hit[..., 2] >= GROUND_Z) & (hit[..., 2] <= 0.0)
    t = np.where(moving, t_obj, t)
    p = d * t[..., None]
    ego = np.asarray(ego, dtype=float)
    obj = np.asarray(obj, dtype=float)
    v = np.where(moving, d @ (obj - ego), -(d @ ego))
    v = v + np.random.default_rng(seed).normal(0.0, noise, v.shape)
    return {"x": p[..., 0].astype(np.float32), "y": p[..., 1].astype(np.float32), "z": p[..., 2].astype(np.float32),
            "v": v.astype(np.float32), "moving": moving, "ego": ego, "obj": obj}
