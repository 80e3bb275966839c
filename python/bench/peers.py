"""Load + world positions with bvhview and with the Python BVH readers one can pip-install: bvhio,
bvhTools, pybvh, and PyMO (from its repository). A benchmark, not a test.

    python3 python/bench/peers.py --big /tmp/big.bvh --folder tests/data/bvh

Every tool runs in a process of its own, so its peak RSS is its own (os.wait4 reports it), under
a memory limit and a time limit. A tool that computes positions one frame at a time in Python is
timed on as many frames as fit in --budget seconds and the rest is extrapolated linearly; the
table says so. A file a tool cannot load is counted, with the error's type.

Each worker waits --settle seconds after its import before timing anything: importing numpy
starts OpenBLAS threads that spin on the cores for about a tenth of a second, and work timed in
that window (a few milliseconds for bvhview on the folder) measures the spinning, not the tool.
Every tool is run --repeat times and its fastest run counts, except a tool whose load +
positions (the measured total, extrapolation included) come to more than --repeat-under seconds
in a run, or whose run failed: it runs once.
"""

import argparse
import json
import os
import platform
import resource
import subprocess
import sys
import tempfile
import time
from pathlib import Path

TOOLS = ["bvhview", "bvhview_many", "bvhio", "bvhtools", "pybvh", "pymo"]


# Workers: each loads one file and computes the world position of every joint on every frame.
# They return (points per frame, frames computed, frames in the take).


# With --rotations, the tools that give local rotations also compute every joint's local
# rotation as a quaternion on every frame (bvhview and pybvh; the others have no such call).
ROTATIONS = os.environ.get("PEERS_ROTATIONS") == "1"
ROTATING_TOOLS = ["bvhview", "bvhview_many", "pybvh"]


def work_bvhview(path, budget):
    import bvhview

    take = bvhview.load(path)
    yield "loaded"
    points = take.positions()
    if ROTATIONS:
        take.local_rotations(kind="quat")
    yield points.shape[1], points.shape[0], points.shape[0]


def work_pybvh(path, budget):
    import pybvh

    take = pybvh.read_bvh_file(path, world_up="+y", warn_on_world_up_disagreement=False)
    yield "loaded"
    points = take.node_positions()  # vectorised over frames
    if ROTATIONS:
        take.to_quat()  # (root positions, every joint's local quaternion on every frame)
    yield points.shape[1], points.shape[0], points.shape[0]


def work_pymo(path, budget):
    import warnings

    warnings.simplefilter("ignore")
    from pymo.parsers import BVHParser
    from pymo.preprocessing import MocapParameterizer

    take = BVHParser().parse(str(path))
    yield "loaded"
    positions = MocapParameterizer("position").fit_transform([take])[0].values
    frames = len(positions.index)
    yield len(positions.columns) // 3, frames, frames


def work_bvhio(path, budget):
    import bvhio

    root = bvhio.readAsHierarchy(str(path))
    yield "loaded"
    joints = [joint for joint, _, _ in root.layout()]
    frames = root.getKeyframeRange()[1] + 1
    deadline = time.perf_counter() + budget
    done = 0
    for frame in range(frames):
        root.loadPose(frame)
        [joint.PositionWorld for joint in joints]
        done += 1
        if time.perf_counter() > deadline:
            break
    yield len(joints), done, frames


def work_bvhtools(path, budget):
    from bvhTools import bvhIO

    take = bvhIO.readBvh(str(path))
    yield "loaded"
    frames = take.motion.numFrames
    deadline = time.perf_counter() + budget
    done = points = 0
    for frame in range(frames):
        points = len(take.getFKAtFrame(frame))
        done += 1
        if time.perf_counter() > deadline:
            break
    yield points, done, frames


def worker_many(paths):
    """bvhview's bulk loader: the whole folder in one `load_many` call (on every core), then
    positions take by take. The batch's load time is carried by the first file's record."""
    import bvhview

    started = time.perf_counter()
    takes = bvhview.load_many(paths, errors="return")
    batch = time.perf_counter() - started
    for index, (path, take) in enumerate(zip(paths, takes)):
        record = {"path": str(path), "load": batch if index == 0 else 0.0, "batch": index == 0}
        if isinstance(take, Exception):
            record["error"] = f"{type(take).__name__}: {str(take)[:120]}"
        else:
            started = time.perf_counter()
            points = take.positions()
            if ROTATIONS:
                take.local_rotations(kind="quat")
            record["positions"] = time.perf_counter() - started
            record["points"], record["done"], record["frames"] = (
                points.shape[1], points.shape[0], points.shape[0])
        print(json.dumps(record), flush=True)


def worker(tool, paths, budget, settle):
    """Runs in the child: one JSON line per file."""
    if tool == "bvhview_many":
        started = time.perf_counter()
        __import__("bvhview")
        print(json.dumps({"import": time.perf_counter() - started}), flush=True)
        time.sleep(settle)
        return worker_many(paths)
    work = globals()[f"work_{tool}"]
    # The import is the tool's fixed cost, not the files'; it is timed apart.
    started = time.perf_counter()
    __import__({"bvhtools": "bvhTools.bvhIO", "pymo": "pymo.preprocessing"}.get(tool, tool))
    print(json.dumps({"import": time.perf_counter() - started}), flush=True)
    time.sleep(settle)
    for path in paths:
        record = {"path": str(path)}
        started = time.perf_counter()
        try:
            steps = work(path, budget)
            next(steps)
            record["load"] = time.perf_counter() - started
            started = time.perf_counter()
            record["points"], record["done"], record["frames"] = next(steps)
            record["positions"] = time.perf_counter() - started
        except Exception as error:  # a peer's failure on a real file is a result, not a crash
            record["error"] = f"{type(error).__name__}: {str(error)[:120]}"
        print(json.dumps(record), flush=True)


def run(command, timeout, memory_gb):
    """Runs `command` under an address-space limit: (stdout, stderr, peak RSS in MB, exit code
    or "timeout"). The peak comes from wait4's rusage of this very child."""

    def limits():
        limit = int(memory_gb * 2**30)
        resource.setrlimit(resource.RLIMIT_AS, (limit, limit))

    with tempfile.TemporaryFile("w+") as out, tempfile.TemporaryFile("w+") as err:
        child = subprocess.Popen(command, stdout=out, stderr=err, preexec_fn=limits, text=True)
        deadline = time.monotonic() + timeout
        while True:
            pid, status, usage = os.wait4(child.pid, os.WNOHANG)
            if pid:
                code = os.waitstatus_to_exitcode(status)
                break
            if time.monotonic() > deadline:
                child.kill()
                _, _, usage = os.wait4(child.pid, 0)
                code = "timeout"
                break
            time.sleep(0.02)
        child.returncode = 0  # reaped here: Popen must not wait for it again
        out.seek(0)
        err.seek(0)
        return out.read(), err.read(), usage.ru_maxrss / 1024, code


def run_tool(tool, python, paths, budget, settle, timeout, memory_gb):
    """One child process per tool and data set: (per-file records, peak RSS MB, failure)."""
    command = [python, __file__, "--worker", tool, "--budget", str(budget), "--settle", str(settle),
               *map(str, paths)]
    out, err, rss, code = run(command, timeout, memory_gb)
    records = [json.loads(line) for line in out.splitlines() if line.startswith("{")]
    failure = None
    if code == "timeout":
        failure = f"over the {timeout:.0f} s limit"
    elif code != 0:
        last = (err.strip().splitlines() or [f"exit {code}"])[-1]
        failure = f"crashed ({last[:100]})"
    return records, rss, failure


def summarise(records, only=None):
    """Totals over the files loaded (of `only`, when given: the files another tool loaded)."""
    loaded = [
        r for r in records
        if "path" in r and "error" not in r and (only is None or r["path"] in only)
    ]
    failed = [r for r in records if "error" in r]
    # A batch load counts whole, whichever files are compared (so load_many is run again on
    # exactly the files a peer loaded: see main).
    load = sum(r["load"] for r in loaded) + sum(
        r["load"] for r in records if r.get("batch") and r not in loaded)
    # Positions of the frames not computed within the budget, at the rate of those that were.
    positions = sum(r["positions"] * r["frames"] / max(r["done"], 1) for r in loaded)
    return {
        "loaded": len(loaded),
        "loaded_paths": sorted(r["path"] for r in loaded),
        "failed": len(failed),
        "errors": sorted({r["error"].split(":")[0] for r in failed}),
        "load": load,
        "positions": positions,
        "total": load + positions,
        "extrapolated": any(r["done"] < r["frames"] for r in loaded),
        "frames": sum(r["frames"] for r in loaded),
        "points": max((r["points"] for r in loaded), default=0),
    }


def main():
    parser = argparse.ArgumentParser(
        description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter
    )
    parser.add_argument("--worker", help=argparse.SUPPRESS)
    parser.add_argument("paths", nargs="*", help=argparse.SUPPRESS)
    parser.add_argument("--big", type=Path, help="the 100 MB file of the bench (see docs/PERFORMANCE.md)")
    parser.add_argument("--folder", type=Path, help="a folder of real .bvh files")
    parser.add_argument("--tools", default=",".join(TOOLS), help="of: " + ", ".join(TOOLS))
    parser.add_argument("--python", default=sys.executable, help="the Python with the tools")
    parser.add_argument(
        "--cli", type=Path, default=Path(__file__).resolve().parents[2] / "target/release/bvhview"
    )
    parser.add_argument("--budget", type=float, default=60,
                        help="seconds of frame-by-frame positions before extrapolating")
    parser.add_argument("--timeout", type=float, default=900, help="seconds per tool and data set")
    parser.add_argument("--memory-gb", type=float, default=12, help="address-space limit per tool")
    parser.add_argument("--settle", type=float, default=0.5,
                        help="seconds each worker waits after its import before timing")
    parser.add_argument("--repeat", type=int, default=3,
                        help="runs of each tool; the fastest counts")
    parser.add_argument("--repeat-under", type=float, default=10,
                        help="a tool whose load + positions take longer than this many seconds "
                             "in a run runs once")
    parser.add_argument("--json", type=Path, help="also write every figure here")
    parser.add_argument("--rotations", action="store_true",
                        help="positions and local rotations (quaternions): bvhview, pybvh only")
    args = parser.parse_args()
    if args.repeat < 1:
        parser.error("--repeat must be at least 1")
    if args.worker:
        return worker(args.worker, [Path(p) for p in args.paths], args.budget, args.settle)

    sets = []
    if args.big:
        sets.append((f"{args.big.name} ({args.big.stat().st_size / 1e6:.1f} MB)", [args.big]))
    if args.folder:
        files = sorted(args.folder.glob("*.bvh"))
        size = sum(f.stat().st_size for f in files) / 1e6
        sets.append((f"{args.folder} ({len(files)} files, {size:.1f} MB)", files))
    if not sets:
        parser.error("give --big, --folder or both")
    tools = args.tools.split(",")
    if args.rotations:
        others = [t for t in tools if t not in ROTATING_TOOLS]
        if args.tools == ",".join(TOOLS):
            tools = ROTATING_TOOLS
        elif others:
            parser.error(f"--rotations: {', '.join(others)} give no local rotations")
        # The workers are children: they read it from their environment.
        os.environ["PEERS_ROTATIONS"] = "1"

    print(f"# {time.strftime('%Y-%m-%d')}, {os.cpu_count()} cores, "
          f"{platform.processor() or platform.machine()}, Python {platform.python_version()}")
    results = {}
    for name, paths in sets:
        print(f"\n## {name}", flush=True)
        for tool in tools:
            best = None
            for _ in range(args.repeat):
                run_ = run_tool(tool, args.python, paths, args.budget, args.settle, args.timeout,
                                args.memory_gb)
                if best is None or (
                    not run_[2] and summarise(run_[0])["total"] < summarise(best[0])["total"]
                ):
                    best = run_
                if run_[2] or summarise(run_[0])["total"] > args.repeat_under:
                    break
            records, rss, failure = best
            summary = summarise(records)
            summary.update(rss_mb=rss, failure=failure, records=records)
            results[(name, tool)] = summary
            print(f"{tool:9} loaded {summary['loaded']}/{len(paths)}, load {summary['load']:.3f} s, "
                  f"positions {summary['positions']:.3f} s"
                  f"{' (extrapolated)' if summary['extrapolated'] else ''}, peak RSS {rss:.0f} MB"
                  f"{', ' + failure if failure else ''} {summary['errors'] or ''}", flush=True)
        if "bvhview_many" in tools:
            # One load_many call holds the whole batch, so it cannot be cut to the files a peer
            # loaded afterwards: it runs again on exactly those files, for a like-for-like ratio.
            for tool in tools:
                loaded = results[(name, tool)].get("loaded_paths")
                if tool.startswith("bvhview") or not loaded or len(loaded) == len(paths):
                    continue
                same = [Path(p) for p in loaded]
                best = None
                for _ in range(args.repeat):
                    run_ = run_tool("bvhview_many", args.python, same, args.budget, args.settle,
                                    args.timeout, args.memory_gb)
                    if best is None or (
                        not run_[2] and summarise(run_[0])["total"] < summarise(best[0])["total"]
                    ):
                        best = run_
                results[(name, f"bvhview_many on {tool}'s files")] = {"records": best[0]}
        if args.cli.is_file():
            target = paths[0] if len(paths) == 1 else paths[0].parent
            _, _, rss, code = run([str(args.cli), "info", str(target)], args.timeout, args.memory_gb)
            results[(name, "cli")] = {"rss_mb": rss}
            print(f"bvhview CLI info: peak RSS {rss:.0f} MB (exit {code})", flush=True)
        _, _, rss, _ = run([args.python, "-c", "import numpy, bvhview"], 60, args.memory_gb)
        results[(name, "python")] = {"rss_mb": rss}
        print(f"Python with numpy and bvhview imported: peak RSS {rss:.0f} MB", flush=True)

    print_table(sets, tools, results)
    if args.json:
        args.json.write_text(json.dumps({f"{k[0]} | {k[1]}": v for k, v in results.items()}, indent=1))


def print_table(sets, tools, results):
    many = "bvhview_many" in tools
    print("\n| data | tool | files loaded | load s | positions s | load + positions s "
          "| bvhview × faster |" + (" bvhview load_many × faster |" if many else "") + " peak RSS MB |")
    print("|---|---|---|---|---|---|---|" + ("---|" if many else "") + "---|")
    for name, paths in sets:
        ours = results[(name, "bvhview")]
        for tool in tools:
            r = results[(name, tool)]
            if r["failure"]:
                print(f"| {name} | {tool} | {r['failure']} | | | | | {r['rss_mb']:.0f} |")
                continue
            loaded = f"{r['loaded']}/{len(paths)}"
            if r["failed"]:
                loaded += f" ({r['failed']} failed: {', '.join(r['errors'])})"
            mark = " (extrapolated)" if r["extrapolated"] else ""
            # Against bvhview on the same files: those this tool loaded.
            same = summarise(ours["records"], only=set(r["loaded_paths"]))
            ratio = "1" if tool.startswith("bvhview") else f"{r['total'] / same['total']:,.0f}"
            extra = ""
            if many:
                own = results.get((name, f"bvhview_many on {tool}'s files"),
                                  results[(name, "bvhview_many")])
                bulk = summarise(own["records"], only=set(r["loaded_paths"]))
                extra = (" 1 |" if tool.startswith("bvhview")
                         else f" {r['total'] / bulk['total']:,.0f} |")
            print(f"| {name} | {tool} | {loaded} | {r['load']:.3f} | {r['positions']:.3f}{mark} | "
                  f"{r['total']:.3f} | {ratio} |{extra} {r['rss_mb']:.0f} |")
        if (name, "cli") in results:
            print(f"| {name} | bvhview CLI `info` (loads, no positions) | | | | | | "
                  f"{results[(name, 'cli')]['rss_mb']:.0f} |")
        print(f"| {name} | Python + numpy + bvhview imported, nothing loaded | | | | | | "
              f"{results[(name, 'python')]['rss_mb']:.0f} |")


if __name__ == "__main__":
    sys.exit(main())
