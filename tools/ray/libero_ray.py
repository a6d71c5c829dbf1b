"""Ray driver for `libero optimize --ray` and `libero series --ray`.

The `libero` program starts this module with the project's virtualenv Python and talks to it in
JSON lines (one object a line):

  stdin   {"op": "job", "id": N, "argv": [...], "timeout_s": T}   run `libero ARGV` on a worker
          {"op": "cancel"}                                        drop every job in flight
          end of input                                            finish what is in flight, exit
  stdout  {"event": "ready", "nodes": [...], "ray": "2.x"}        the cluster checked, jobs welcome
          {"event": "refused", "error": "..."}                    a node cannot run our jobs
          {"event": "done", "id": N, "ok": true, "report": {...}, "node": "...", "wall_s": W, "cpu_s": C}
          {"event": "done", "id": N, "ok": false, "error": "...", "node": "..."}

Each job is a Ray task that unpacks the bundle (the `libero` binary and its data files, sent once
through the object store and cached per node by content hash), starts the job's own fast-mode
server through `libero`, and returns the report the command wrote to the `{report}` path of its
argv. A task whose worker or node dies is retried elsewhere by Ray (`--max-retries`); a job that
fails by itself (the command exits non-zero) is reported, not retried.
"""

import argparse
import ctypes
import hashlib
import io
import json
import os
import platform
import resource
import shutil
import signal
import subprocess
import sys
import tarfile
import tempfile
import threading
import time

CACHE = os.path.join(
    os.environ.get("XDG_CACHE_HOME") or os.path.join(os.path.expanduser("~"), ".cache"),
    "libero",
)


def log(message):
    print(f"libero_ray: {message}", file=sys.stderr, flush=True)


def emit(event):
    sys.stdout.write(json.dumps(event) + "\n")
    sys.stdout.flush()


def pack(folder):
    """The bundle as gzip'd tar bytes and their SHA-256."""
    buffer = io.BytesIO()
    with tarfile.open(fileobj=buffer, mode="w:gz", compresslevel=1) as tar:
        tar.add(folder, arcname=".")
    data = buffer.getvalue()
    return data, hashlib.sha256(data).hexdigest()


def die_with_parent():
    # A job's `libero` (and through it its server) dies with the Ray worker that ran it, so a
    # killed worker leaves no orphan server behind. PR_SET_PDEATHSIG = 1.
    ctypes.CDLL("libc.so.6", use_errno=True).prctl(1, signal.SIGKILL)
    os.setpgid(0, 0)


def unpacked(box, digest):
    """The bundle's folder on this node, unpacked on first use (atomically, by rename)."""
    import ray

    root = os.path.join(CACHE, "bundles", digest[:20])
    if os.path.isfile(os.path.join(root, "libero")):
        return root
    os.makedirs(os.path.dirname(root), exist_ok=True)
    staging = tempfile.mkdtemp(prefix=".unpack-", dir=os.path.dirname(root))
    data = ray.get(box[0])
    if hashlib.sha256(data).hexdigest() != digest:
        raise RuntimeError("the bundle arrived damaged (its hash does not match)")
    with tarfile.open(fileobj=io.BytesIO(data), mode="r:gz") as tar:
        tar.extractall(staging, filter="data")
    try:
        os.rename(staging, root)
    except OSError:
        # Another task on this node unpacked it first.
        shutil.rmtree(staging, ignore_errors=True)
    return root


def worker_venv(pins):
    """The virtualenv a worker's servers run from: LIBERO_VENV if the node sets it, else a
    per-user cache named by the pinned rcsssmj (installed there by `libero` on first use)."""
    return os.environ.get("LIBERO_VENV") or os.path.join(
        CACHE, f"venv-rcsssmj-{pins['rcsssmj']}"
    )


def installed_rcsssmj(venv):
    python = os.path.join(venv, "bin", "python")
    if not os.path.exists(python):
        return None
    probe = subprocess.run(
        [python, "-c", "import importlib.metadata as m; print(m.version('rcsssmj'))"],
        capture_output=True,
        text=True,
        timeout=60,
    )
    return probe.stdout.strip() if probe.returncode == 0 else None


def node_facts(box, digest, pins):
    """What a node offers, and what stops it from running our jobs (`problems`)."""
    import ray

    problems = []
    facts = {
        "node": ray.get_runtime_context().get_node_id(),
        "host": platform.node(),
        "platform": f"{platform.system()}-{platform.machine()}",
        "python": platform.python_version(),
        "ray": ray.__version__,
    }
    if facts["ray"] != pins["ray"]:
        problems.append(f"Ray {facts['ray']}, the driver has {pins['ray']}")
    venv = worker_venv(pins)
    facts["venv"] = venv
    found = installed_rcsssmj(venv)
    facts["rcsssmj"] = found
    if found is not None and found != pins["rcsssmj"]:
        problems.append(
            f"rcsssmj {found} in {venv}, this libero needs {pins['rcsssmj']} "
            "(point LIBERO_VENV at a virtualenv with it, or unset it for the cache venv)"
        )
    try:
        root = unpacked(box, digest)
        version = subprocess.run(
            [os.path.join(root, "libero"), "--version"],
            capture_output=True,
            text=True,
            timeout=60,
        )
        facts["libero"] = version.stdout.strip()
        if version.returncode != 0 or facts["libero"] != pins["libero"]:
            problems.append(
                f"the bundled libero does not run here ({facts['platform']}): "
                f"{(version.stderr or version.stdout).strip()[:300]}"
            )
    except Exception as e:  # noqa: BLE001 - any failure is the node's problem to report
        problems.append(f"the bundle cannot be unpacked or run: {e}")
    facts["problems"] = problems
    return facts


def run_job(job, box, digest, pins):
    """One job on this node: `libero ARGV` in the bundle, its report read back."""
    import ray

    node = ray.get_runtime_context().get_node_id()
    root = unpacked(box, digest)
    venv = worker_venv(pins)
    found = installed_rcsssmj(venv)
    if found is not None and found != pins["rcsssmj"]:
        return {"ok": False, "node": node, "error": f"rcsssmj {found} in {venv}, needs {pins['rcsssmj']}"}
    with tempfile.TemporaryDirectory(prefix="libero-job-") as scratch:
        report = os.path.join(scratch, "report.json")
        argv = [a.replace("{report}", report) for a in job["argv"]]
        env = dict(os.environ, LIBERO_HOME=root, LIBERO_VENV=venv)
        before = resource.getrusage(resource.RUSAGE_CHILDREN)
        began = time.monotonic()
        try:
            done = subprocess.run(
                [os.path.join(root, "libero"), *argv],
                cwd=root,
                env=env,
                stdout=subprocess.PIPE,
                stderr=subprocess.STDOUT,
                timeout=job.get("timeout_s"),
                preexec_fn=die_with_parent,
            )
        except subprocess.TimeoutExpired as e:
            tail = (e.output or b"")[-2000:].decode(errors="replace")
            return {"ok": False, "node": node, "error": f"timed out after {job.get('timeout_s')} s\n{tail}"}
        wall = time.monotonic() - began
        after = resource.getrusage(resource.RUSAGE_CHILDREN)
        cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
        output = done.stdout[-4000:].decode(errors="replace")
        if done.returncode != 0:
            return {"ok": False, "node": node, "error": f"exit code {done.returncode}\n{output}"}
        try:
            with open(report) as f:
                result = json.load(f)
        except (OSError, ValueError) as e:
            return {"ok": False, "node": node, "error": f"no report ({e})\n{output}"}
        return {"ok": True, "node": node, "report": result, "wall_s": wall, "cpu_s": cpu}


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--address", required=True, help="the Ray cluster (HOST:PORT)")
    parser.add_argument("--bundle", required=True, help="folder with libero and its data files")
    parser.add_argument("--libero-version", required=True)
    parser.add_argument("--rcsssmj", required=True, help="the pinned server version")
    parser.add_argument("--max-retries", type=int, default=3)
    args = parser.parse_args()

    import ray
    from ray.util.scheduling_strategies import NodeAffinitySchedulingStrategy

    pins = {"ray": ray.__version__, "rcsssmj": args.rcsssmj, "libero": args.libero_version}
    try:
        ray.init(address=args.address, logging_level="ERROR", log_to_driver=False)
    except Exception as e:  # noqa: BLE001 - told to the user as it is
        emit({"event": "refused", "error": f"cannot join the Ray cluster at {args.address}: {e}"})
        return 2
    data, digest = pack(args.bundle)
    log(f"bundle {len(data) / 1e6:.1f} MB, sha256 {digest[:12]}")
    box = [ray.put(data)]
    del data

    probe = ray.remote(num_cpus=0)(node_facts)
    nodes = [n for n in ray.nodes() if n.get("Alive") and n.get("Resources", {}).get("CPU", 0) > 0]
    if not nodes:
        emit({"event": "refused", "error": f"the Ray cluster at {args.address} has no node with a CPU"})
        return 2
    facts = ray.get(
        [
            probe.options(
                scheduling_strategy=NodeAffinitySchedulingStrategy(n["NodeID"], soft=False)
            ).remote(box, digest, pins)
            for n in nodes
        ]
    )
    for n, f in zip(nodes, facts):
        f["cpus"] = n["Resources"].get("CPU", 0)
    refused = [f for f in facts if f["problems"]]
    if refused:
        lines = [f"node {f['host']} ({f['node'][:8]}): {'; '.join(f['problems'])}" for f in refused]
        emit({"event": "refused", "error": "\n".join(lines)})
        return 2
    emit({"event": "ready", "nodes": facts, "ray": ray.__version__})

    task = ray.remote(num_cpus=1, max_retries=args.max_retries, retry_exceptions=False)(run_job)
    pending = {}
    lock = threading.Lock()
    ended = threading.Event()

    def read_commands():
        for line in sys.stdin:
            line = line.strip()
            if not line:
                continue
            try:
                command = json.loads(line)
            except ValueError:
                log(f"ignored a line that is not JSON: {line[:80]}")
                continue
            if command.get("op") == "job":
                ref = task.remote(command, box, digest, pins)
                with lock:
                    pending[ref] = command["id"]
            elif command.get("op") == "cancel":
                with lock:
                    refs = list(pending)
                for ref in refs:
                    ray.cancel(ref, force=True)
        ended.set()

    threading.Thread(target=read_commands, daemon=True).start()
    while True:
        with lock:
            refs = list(pending)
        if not refs:
            if ended.is_set():
                break
            time.sleep(0.05)
            continue
        done, _ = ray.wait(refs, num_returns=1, timeout=0.2)
        for ref in done:
            with lock:
                job_id = pending.pop(ref)
            try:
                result = ray.get(ref)
            except ray.exceptions.TaskCancelledError:
                result = {"ok": False, "error": "cancelled", "node": None}
            except Exception as e:  # noqa: BLE001 - a lost task after its retries
                result = {"ok": False, "error": f"the task was lost: {e}", "node": None}
            emit({"event": "done", "id": job_id, **result})
    return 0


if __name__ == "__main__":
    sys.exit(main())
