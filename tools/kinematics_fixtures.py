#!/usr/bin/env python3
"""Forward-kinematics fixtures for libero-model, computed by MuJoCo on the server's own robot files.

For each robot (T1, K1) this loads rcsssmj's `resources/robots/<ROBOT>/robot.xml`, sets random joint
angles drawn uniformly within the joint ranges, runs `mj_kinematics`, and records for every actuated
joint the pose of the body that joint moves, plus the sites, all relative to the torso body. Joints
are keyed by their `jointpos` sensor name (`q_hj1`, ...), the names the Rust model knows as
`perceptor`.

Usage:  <python-with-rcsssmj> tools/kinematics_fixtures.py [--poses 50] [--seed 1] [--out DIR]
Run it with the interpreter of the venv that has rcsssmj and mujoco installed, e.g.
/work/main/.venv/bin/python or /tmp/probe-venv/bin/python.
"""

import argparse
import importlib.metadata
import json
import math
import pathlib
import random

import mujoco
import numpy as np
import rcsssmj

ROBOTS = ("T1", "K1")
SITES = ("camera", "head-vismarker", "lfoot-vismarker", "rfoot-vismarker")


def robot_xml(robot: str) -> pathlib.Path:
    return pathlib.Path(rcsssmj.__file__).parent / "resources" / "robots" / robot / "robot.xml"


def relative_pose(torso_pos, torso_mat, pos, mat):
    rel_pos = torso_mat.T @ (pos - torso_pos)
    rel_mat = torso_mat.T @ mat
    quat = np.zeros(4)
    mujoco.mju_mat2Quat(quat, rel_mat.flatten())
    if quat[0] < 0:
        quat = -quat
    return {"pos": [round(float(v), 7) for v in rel_pos], "quat": [round(float(v), 7) for v in quat]}


def fixtures_for(robot: str, poses: int, rng: random.Random) -> dict:
    model = mujoco.MjModel.from_xml_path(str(robot_xml(robot)))
    data = mujoco.MjData(model)
    torso = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_BODY, "torso")
    sensors = []
    for s in range(model.nsensor):
        if model.sensor_type[s] == mujoco.mjtSensor.mjSENS_JOINTPOS:
            name = mujoco.mj_id2name(model, mujoco.mjtObj.mjOBJ_SENSOR, s)
            sensors.append((name, int(model.sensor_objid[s])))
    sites = [(n, mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_SITE, n)) for n in SITES]
    records = []
    for _ in range(poses):
        data.qpos[:] = model.qpos0
        # A torso pose that is not the identity, so the fixtures also prove the torso-relative transform.
        data.qpos[0:3] = [rng.uniform(-5, 5), rng.uniform(-5, 5), rng.uniform(0, 1)]
        q = np.array([rng.gauss(0, 1) for _ in range(4)])
        data.qpos[3:7] = q / np.linalg.norm(q)
        angles = {}
        for name, joint in sensors:
            lo, hi = model.jnt_range[joint]
            angle = rng.uniform(lo, hi)
            data.qpos[model.jnt_qposadr[joint]] = angle
            angles[name] = round(math.degrees(angle), 9)
        mujoco.mj_kinematics(model, data)
        torso_pos = data.xpos[torso].copy()
        torso_mat = data.xmat[torso].reshape(3, 3).copy()
        bodies = {}
        for name, joint in sensors:
            body = model.jnt_bodyid[joint]
            bodies[name] = relative_pose(torso_pos, torso_mat, data.xpos[body], data.xmat[body].reshape(3, 3))
        site_poses = {
            n: relative_pose(torso_pos, torso_mat, data.site_xpos[i], data.site_xmat[i].reshape(3, 3))
            for n, i in sites
            if i >= 0
        }
        records.append({"angles_deg": angles, "joint_bodies": bodies, "sites": site_poses})
    return {
        "robot": robot,
        "source": f"rcsssmj {importlib.metadata.version('rcsssmj')}, mujoco {mujoco.__version__}, {robot}/robot.xml",
        "frame": "poses relative to the torso body: pos [m], quat (w, x, y, z)",
        "poses": records,
    }


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--poses", type=int, default=50)
    parser.add_argument("--seed", type=int, default=1)
    default_out = pathlib.Path(__file__).resolve().parent.parent / "engine" / "model" / "tests" / "fixtures"
    parser.add_argument("--out", type=pathlib.Path, default=default_out)
    args = parser.parse_args()
    args.out.mkdir(parents=True, exist_ok=True)
    for robot in ROBOTS:
        rng = random.Random(f"{args.seed}-{robot}")
        path = args.out / f"fk_{robot.lower()}.json"
        fixtures = fixtures_for(robot, args.poses, rng)
        poses = fixtures.pop("poses")
        # One pose per line: small files whose diffs stay readable.
        header = json.dumps(fixtures, separators=(",", ":"))[:-1]
        body = ",\n".join(json.dumps(p, separators=(",", ":")) for p in poses)
        path.write_text(f'{header},"poses":[\n{body}\n]}}\n')
        print(f"wrote {path}")


if __name__ == "__main__":
    main()
