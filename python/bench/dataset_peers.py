"""Compile a folder of BVH takes into a training dataset with bvhview and with pybvh-ml 0.6.0's
`preprocess_directory`, round-robin. A benchmark, not a test.

    python3 python/bench/dataset_peers.py [FOLDER…] [--rounds 5]

Both tools get the same files (links to every .bvh file under the FOLDERs, and copies with
--copies; default ../shared/data/bvh when present, else tests/data/bvh): bvhview one folder, pybvh-ml one folder
per skeleton topology in turn (it packs one skeleton per dataset). Both are asked for the same work: rotations
as 6D, world positions, velocities and foot contacts, resampled to 30 frames per second, errors
skipped. Each run is a process of its own (its peak RSS is its own getrusage); the time is the
call's own, after the imports. Every round runs every tool in turn, one thread against one
(bvhview `threads=1`, pybvh-ml `parallel=False`), then all threads against all (bvhview's
default, pybvh-ml `parallel=True` with as many workers as cores; its workers are Python threads).
The table gives the median and the fastest round, and the CPU's features.
"""

import argparse
import json
import os
import platform
import shutil
import statistics
import subprocess
import sys
import tempfile
from pathlib import Path

REPO = Path(__file__).resolve().parents[2]

WORKER = r"""
import json, sys, time
tool, threads, folder, out = sys.argv[1], int(sys.argv[2]), sys.argv[3], sys.argv[4]
if tool == "bvhview":
    import bvhview
    start = time.perf_counter()
    manifest = bvhview.compile_dataset(folder, out, fps=30, rotations="6d", threads=threads, parquet=False)
    took = time.perf_counter() - start
    clips = len(manifest["clips"])
    frames = sum(c["frames"] for c in manifest["clips"])
else:
    import os
    from pybvh_ml import preprocess_directory
    # pybvh-ml packs one skeleton per dataset: it is given each topology's folder in turn.
    start = time.perf_counter()
    clips = 0
    for k, group in enumerate(sorted(os.listdir(folder + ".groups"))):
        try:
            preprocess_directory(
                f"{folder}.groups/{group}", f"{out}_{k}.npz", representation="6d",
                center_root=False, include_positions=True, include_velocities=True,
                include_foot_contacts=True, target_fps=30.0, skip_errors=True,
                parallel=threads > 1, max_workers=threads if threads > 1 else None,
            )
            clips += 1
        except Exception as error:  # a folder none of whose files it loads
            print(f"{group}: {type(error).__name__}", file=sys.stderr)
    took = time.perf_counter() - start
    frames = None
import resource
peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024
print(json.dumps({"seconds": took, "clips": clips, "frames": frames, "rss_mb": peak}))
"""


def cpu_features() -> str:
    flags: set[str] = set()
    model = platform.processor()
    try:
        for line in open("/proc/cpuinfo"):
            if line.startswith("flags"):
                flags = set(line.split(":")[1].split())
            if line.startswith("model name"):
                model = line.split(":")[1].strip()
    except OSError:
        pass
    wanted = [f for f in ("avx2", "avx512f", "avx512bw", "avx512vl", "avx512vbmi") if f in flags]
    return f"{model}; {os.cpu_count()} cores; {' '.join(wanted) or 'no AVX2'}"


def run(tool: str, threads: int, folder: Path, scratch: Path) -> dict:
    out = tempfile.mkdtemp(dir=scratch)
    os.rmdir(out)
    process = subprocess.Popen(
        [sys.executable, "-c", WORKER, tool, str(threads), str(folder), out],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
    )
    stdout, stderr = process.communicate()
    if process.returncode != 0:
        raise SystemExit(f"{tool} failed:\n{stderr}")
    result: dict = json.loads(stdout.strip().splitlines()[-1])
    return result


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("folders", nargs="*", type=Path)
    parser.add_argument("--rounds", type=int, default=5)
    parser.add_argument(
        "--copies",
        type=int,
        default=1,
        help="take every file this many times (copies: bvhview lists a file reached by two links once)",
    )
    args = parser.parse_args()
    folders = args.folders or [
        REPO.parent / "shared" / "data" / "bvh"
        if (REPO.parent / "shared" / "data" / "bvh").is_dir()
        else REPO / "tests" / "data" / "bvh"
    ]
    scratch = Path(tempfile.mkdtemp(prefix="dataset_peers."))
    flat = scratch / "takes"
    flat.mkdir()
    size = 0
    for folder in folders:
        for path in sorted(folder.rglob("*.bvh")):
            for copy in range(args.copies):
                name = path.name if args.copies == 1 else f"{path.stem}_{copy:03}.bvh"
                link = flat / name
                if not link.exists():
                    # Copies, not links, past the first: bvhview's folder walk lists each file
                    # once however many links lead to it, so links would not make more work.
                    if copy == 0:
                        link.symlink_to(path.resolve())
                    else:
                        shutil.copyfile(path, link)
                    size += path.stat().st_size
    takes = len(list(flat.iterdir()))
    # The same files by skeleton topology (names and parents, as bvhview loads them), for
    # pybvh-ml, which packs one skeleton per dataset.
    groups = Path(str(flat) + ".groups")
    groups.mkdir()
    import bvhview

    topologies: dict = {}
    for link in sorted(flat.iterdir()):
        try:
            take = bvhview.load(link)
        except (ValueError, OSError):
            continue
        key = (tuple(take.joint_names), tuple(take.parents.tolist()))
        folder = groups / f"topology_{topologies.setdefault(key, len(topologies))}"
        folder.mkdir(exist_ok=True)
        (folder / link.name).symlink_to(link.resolve())
    cores = os.cpu_count() or 1
    print(f"CPU: {cpu_features()}")
    copies = f" ({args.copies} links to each)" if args.copies > 1 else ""
    print(
        f"{takes} BVH files{copies}, {size / 1e6:.1f} MB, {len(topologies)} skeleton topologies, from "
        f"{', '.join(map(str, folders))}; {args.rounds} rounds"
    )
    runs = [("bvhview", 1), ("pybvh-ml", 1), ("bvhview", cores), ("pybvh-ml", cores)]
    seconds: dict = {r: [] for r in runs}
    rss: dict = {r: [] for r in runs}
    for round_number in range(args.rounds):
        for tool, threads in runs:
            result = run(tool, threads, flat, scratch)
            seconds[(tool, threads)].append(result["seconds"])
            rss[(tool, threads)].append(result["rss_mb"])
        print(f"round {round_number + 1} done", file=sys.stderr)
    print()
    print("| tool | threads | median s | fastest s | peak RSS MB | bvhview faster (median) |")
    print("|---|---|---|---|---|---|")
    for tool, threads in runs:
        times = seconds[(tool, threads)]
        ours = statistics.median(seconds[("bvhview", threads)])
        ratio = statistics.median(times) / ours
        print(
            f"| {tool} | {threads} | {statistics.median(times):.3f} | {min(times):.3f} | "
            f"{max(rss[(tool, threads)]):.0f} | {'' if tool == 'bvhview' else f'{ratio:.1f}×'} |"
        )
    subprocess.run(["rm", "-rf", str(scratch)], check=False)


if __name__ == "__main__":
    main()
