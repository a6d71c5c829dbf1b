#!/usr/bin/env python3
"""Tabulate how rcssservermj's ball rolls out after a spin-free launch (monitor `(ball (pos)(vel))`).

Loads the server's own world model (resources/environments/soccer/world.xml: ball r 0.11 m,
0.41 kg, solid-sphere inertia, friction 0.4/0.01/0.01, condim 6, pyramidal cone, air density 1.2,
viscosity 2e-5, 5 ms steps) with the `mujoco` package from the venv, launches the ball at rest
with a horizontal velocity, and records for each (launch speed, direction folded into 0–45°):

* where it stops, in the launch frame (along the launch direction, and to its left), and
* the direction of the chord from the launch point to the ball at τ = 0.1 … 0.6 s, relative
  to the launch direction (the path curves towards the field diagonals: MuJoCo's pyramidal
  friction cone is not isotropic), and
* the distance from the launch point at τ = 0.04 … 0.8 s (the slide, then the roll: what the
  launch speed is fitted to from the first observed frames).

By the symmetry of the cone a launch at heading h behaves as one at h mod 90°, mirrored when
that exceeds 45°. Prints the `launch_table` section of engine/world/params/world.ron.

Usage: .venv/bin/python tools/ball_physics.py [--check]
"""
import math
import os
import sys

import mujoco
import numpy as np

import rcsssmj

WORLD = os.path.join(os.path.dirname(rcsssmj.__file__), 'resources/environments/soccer/world.xml')
SPEEDS = [0.5 * i for i in range(1, 21)]
ANGLES = [5.0 * i for i in range(10)]
CHORD_TIMES = [0.1, 0.2, 0.3, 0.4, 0.5, 0.6]
DISTANCE_TIMES = [0.04 * i for i in range(1, 21)]
SUBSTEPS = 4  # server cycle = 4 × 5 ms

MODEL = mujoco.MjModel.from_xml_path(WORLD)


def launch(speed, deg, seconds=16.0):
    """Trajectory [(t, x, y)] every server cycle of a ball launched from rest at (0, 0)."""
    d = mujoco.MjData(MODEL)
    d.qpos[:7] = [0, 0, 0.11, 1, 0, 0, 0]
    mujoco.mj_forward(MODEL, d)
    for _ in range(60 * SUBSTEPS):  # lie still first, as in the live test
        mujoco.mj_step(MODEL, d)
    th = math.radians(deg)
    d.qpos[:7] = [0, 0, 0.11, 1, 0, 0, 0]
    d.qvel[:] = 0
    d.qvel[0:2] = [speed * math.cos(th), speed * math.sin(th)]
    d.qacc[:] = 0
    t0 = d.time
    track = []
    still = 0
    while d.time - t0 < seconds:
        for _ in range(SUBSTEPS):
            mujoco.mj_step(MODEL, d)
        track.append((d.time - t0, d.qpos[0], d.qpos[1]))
        still = still + 1 if np.hypot(d.qvel[0], d.qvel[1]) < 1e-4 else 0
        if still > 10:
            break
    return np.array(track)


def outcome(speed, deg):
    tr = launch(speed, deg)
    th = math.radians(deg)
    e = np.array([math.cos(th), math.sin(th)])
    n = np.array([-e[1], e[0]])
    stop = tr[-1, 1:3]
    chords = []
    for tau in CHORD_TIMES:
        k = int(round(tau / 0.02)) - 1
        p = tr[k, 1:3]
        chords.append(math.degrees(math.atan2(p @ n, p @ e)))
    distances = []
    for tau in DISTANCE_TIMES:
        k = int(round(tau / 0.02)) - 1
        distances.append(float(np.hypot(*tr[min(k, len(tr) - 1), 1:3])))
    return stop @ e, stop @ n, chords, distances


def main():
    if '--check' in sys.argv:
        for h in [22.5, 67.5, 112.5, -22.5, 190.0, -80.0]:
            a, l, _, _ = outcome(5.0, h)
            print(f'heading {h:7.1f}: along {a:.4f} lateral {l:+.4f}')
        return
    print('    launch_table: LaunchTable(')
    print('        speeds: [' + ', '.join(f'{s:.1f}' for s in SPEEDS) + '],')
    print('        angles_deg: [' + ', '.join(f'{a:.1f}' for a in ANGLES) + '],')
    print('        chord_times: [' + ', '.join(f'{t:.1f}' for t in CHORD_TIMES) + '],')
    print('        distance_times: [' + ', '.join(f'{t:.2f}' for t in DISTANCE_TIMES) + '],')
    print('        // Per direction, per launch speed: (stop along, stop to the left [m],')
    print('        // chord direction at each chord time [deg], distance from the launch point at')
    print('        // each distance time [m]).')
    print('        outcomes: [')
    for a in ANGLES:
        print(f'            // {a:.1f}°')
        print('            [')
        for s in SPEEDS:
            al, lat, ch, di = outcome(s, a)
            print(f'                ({al:.4f}, {lat:.4f}, [' + ', '.join(f'{c:.3f}' for c in ch) + '], ['
                  + ', '.join(f'{x:.4f}' for x in di) + ']),')
        print('            ],')
    print('        ],')
    print('    ),')


if __name__ == '__main__':
    main()
