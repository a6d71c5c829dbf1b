#!/usr/bin/env python3
"""Localization error while walking, from evaluation logs.

Usage: libero match --players 3 --duration 40 --log /tmp/m.log
       python3 tools/eval_localization.py /tmp/m.log.*

Counts PlayOn cycles in which the ground-truth torso moved (> 2 mm since the previous cycle) and
stood upright (torso above 0.5 m), once the agent is localized; prints median and p95 of the
position and yaw errors of the agent's own estimate against the server's ground truth.
"""
import json
import math
import sys


def main(paths):
    position, yaw = [], []
    for path in paths:
        previous = None
        with open(path) as f:
            for line in f:
                cycle = json.loads(line)
                truth, me = cycle.get("truth"), cycle["me"]
                if not truth or not me["localized"] or cycle["play_mode"] != "PlayOn":
                    continue
                p = truth["position"]
                moved = previous is not None and math.hypot(p[0] - previous[0], p[1] - previous[1]) > 0.002
                previous = p
                if not moved or p[2] < 0.5:
                    continue
                position.append(math.hypot(me["position"][0] - p[0], me["position"][1] - p[1]))
                yaw.append(abs((me["yaw_deg"] - truth["yaw_deg"] + 180) % 360 - 180))
    if not position:
        sys.exit("no walking cycles in these logs")
    position.sort()
    yaw.sort()

    def q(v, f):
        return v[int((len(v) - 1) * f)]

    print(
        f"{len(position)} walking cycles: position median {q(position, .5):.3f} m, "
        f"p95 {q(position, .95):.3f} m; yaw median {q(yaw, .5):.2f} deg, p95 {q(yaw, .95):.2f} deg"
    )


if __name__ == "__main__":
    main(sys.argv[1:])
