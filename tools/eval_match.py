#!/usr/bin/env python3
"""A match's flow and its falls, from the evaluation logs of one team.

Usage: libero match --away tools/teams/standing --duration 300 --log /tmp/m/log
       python3 tools/eval_match.py falls /tmp/m/log Libero
       python3 tools/eval_match.py flow /tmp/m/log Libero [every_s]
       python3 tools/eval_match.py tilt /tmp/m/log Libero

`falls`: each fall in PlayOn (ground-truth torso below 0.35 m), with where, the nearest teammate
over the 2.5 s before (a collision shows as a few decimetres) and the torso's pitch and roll
1.5 s before (a forward runaway shows as 10-20 deg of pitch).
`flow`: every `every_s` (2) seconds the play mode, the ball (as the team's freshest sighting has
it) and each player's ground-truth place and distance to the ball (F: down).
`tilt`: the agents' own torso pitch and roll against the ground truth while upright in PlayOn
(mean, rms, 1st/5th/95th/99th percentiles of estimate − truth) and over the 1.5 s before each
fall, where a lagging estimate hides a forward runaway from the walk's balance loop.
"""
import bisect
import json
import math
import sys

DOWN_M = 0.35


def load(prefix, team):
    tracks = {}
    for unum in range(1, 12):
        try:
            with open(f"{prefix}.{team}.{unum}") as f:
                rows = [json.loads(line) for line in f if line.strip()]
        except FileNotFoundError:
            continue
        tracks[unum] = [r for r in rows if r.get("truth")]
    return tracks


def at(track, times, t):
    i = min(bisect.bisect_left(times, t), len(track) - 1)
    return track[i]


def falls(tracks):
    times = {u: [r["time"] for r in tr] for u, tr in tracks.items()}
    for u, track in tracks.items():
        was_down = None
        for r in track:
            p = r["truth"]["position"]
            down = p[2] < DOWN_M
            if down and was_down is False and r["play_mode"] == "PlayOn":
                t = r["time"]
                nearest = None
                for v in tracks:
                    if v == u:
                        continue
                    for k in range(25):
                        a = at(tracks[v], times[v], t - 0.1 * k)["truth"]["position"]
                        b = at(track, times[u], t - 0.1 * k)["truth"]["position"]
                        d = math.hypot(a[0] - b[0], a[1] - b[1])
                        if nearest is None or d < nearest[0]:
                            nearest = (d, v)
                before = at(track, times[u], t - 1.5)["truth"]
                near = f"{nearest[1]} at {nearest[0]:.2f} m" if nearest else "-"
                print(
                    f"{u} fell at {t:6.1f} s at ({p[0]:6.1f}, {p[1]:5.1f}); nearest teammate {near}; "
                    f"1.5 s before: pitch {before['pitch_deg']:5.1f} roll {before['roll_deg']:5.1f} deg"
                )
            was_down = down


def flow(tracks, every):
    rows = {}
    for u, track in tracks.items():
        for r in track:
            rows.setdefault(round(r["time"], 2), {})[u] = r
    due = 0.0
    for t in sorted(rows):
        if t < due:
            continue
        due = t + every
        now = rows[t]
        sightings = [r["ball"] for r in now.values()
                     if r.get("ball") and r["ball"]["last_seen_time"] is not None]
        ball = max(sightings, key=lambda b: b["last_seen_time"])["position"] if sightings else [0.0, 0.0]
        mode = next(iter(now.values()))["play_mode"]
        players = []
        for u in sorted(tracks):
            if u not in now:
                continue
            p = now[u]["truth"]["position"]
            mark = "F" if p[2] < DOWN_M else " "
            d = math.hypot(p[0] - ball[0], p[1] - ball[1])
            players.append(f"{u}:{p[0]:5.1f},{p[1]:5.1f}{mark}d{d:4.1f}")
        print(f"{t:6.1f} {mode[:10]:10s} ball {ball[0]:6.1f},{ball[1]:5.1f} | " + " ".join(players))


def spread(errors):
    if not errors:
        return "no cycles"
    e = sorted(errors)
    n = len(e)
    q = lambda f: e[min(n - 1, int(f * n))]
    rms = math.sqrt(sum(x * x for x in e) / n)
    return (f"n {n} mean {sum(e) / n:+.2f} rms {rms:.2f} p1 {q(0.01):+.2f} p5 {q(0.05):+.2f} "
            f"p95 {q(0.95):+.2f} p99 {q(0.99):+.2f} deg")


def tilt(tracks):
    upright = {"pitch": [], "roll": []}
    before_falls = {"pitch": [], "roll": []}
    for track in tracks.values():
        times = [r["time"] for r in track]
        was_down = None
        for i, r in enumerate(track):
            truth = r["truth"]
            if truth.get("pitch_deg") is None:
                continue
            down = truth["position"][2] < DOWN_M
            if r["play_mode"] == "PlayOn" and not down:
                for axis in upright:
                    upright[axis].append(r["me"][f"{axis}_deg"] - truth[f"{axis}_deg"])
            if down and was_down is False and r["play_mode"] == "PlayOn":
                for q in track[bisect.bisect_left(times, r["time"] - 1.5):i]:
                    if q["truth"]["position"][2] >= DOWN_M:
                        for axis in before_falls:
                            before_falls[axis].append(q["me"][f"{axis}_deg"] - q["truth"][f"{axis}_deg"])
            was_down = down
    for axis in upright:
        print(f"{axis} upright: {spread(upright[axis])}")
        print(f"{axis} 1.5 s before a fall: {spread(before_falls[axis])}")


def main(args):
    what, prefix, team = args[0], args[1], args[2]
    tracks = load(prefix, team)
    if what == "falls":
        falls(tracks)
    elif what == "tilt":
        tilt(tracks)
    elif what == "flow":
        flow(tracks, float(args[3]) if len(args) > 3 else 2.0)
    else:
        sys.exit(__doc__)


if __name__ == "__main__":
    main(sys.argv[1:])
