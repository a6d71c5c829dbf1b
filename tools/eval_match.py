#!/usr/bin/env python3
"""A match's flow and its falls, from the evaluation logs of one team.

Usage: libero match --away tools/teams/standing --duration 300 --log /tmp/m/log
       python3 tools/eval_match.py falls /tmp/m/log Libero
       python3 tools/eval_match.py flow /tmp/m/log Libero [every_s]

`falls`: each fall in PlayOn (ground-truth torso below 0.35 m), with where, the nearest teammate
over the 2.5 s before (a collision shows as a few decimetres) and the torso's pitch and roll
1.5 s before (a forward runaway shows as 10-20 deg of pitch).
`flow`: every `every_s` (2) seconds the play mode, the ball (as the team's freshest sighting has
it) and each player's ground-truth place and distance to the ball (F: down).
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
        sightings = [r["ball"] for r in now.values() if r["ball"]["last_seen_time"] is not None]
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


def main(args):
    what, prefix, team = args[0], args[1], args[2]
    tracks = load(prefix, team)
    if what == "falls":
        falls(tracks)
    elif what == "flow":
        flow(tracks, float(args[3]) if len(args) > 3 else 2.0)
    else:
        sys.exit(__doc__)


if __name__ == "__main__":
    main(sys.argv[1:])
