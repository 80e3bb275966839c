"""convert's canonical layout (`--channels root6,rot3 --order ZYX --strip-prefix`, and `--order XYZ`
alone) read back by two BVH readers that owe nothing to bvhview, bvhio and pybvh: their world
positions of the output at frames 0, 1, N/2 and N-1 are the source's as `bvhview positions` gives
them, within 1e-4 of the figure's height.

Each peer reads the source too: where it refuses the source, or reads it otherwise than bvhview
does, the file shows a limit of that peer and is skipped for it (with the reason, said in the
summary). The test fails only where a peer reads the source right and the output wrong."""

import csv
import re
import subprocess
import warnings
from pathlib import Path

import numpy as np
import pytest

from conftest import DATA, SHARED

TOLERANCE = 1e-4  # of the figure's height
RUNS = {
    "canonical": ["--channels", "root6,rot3", "--order", "ZYX", "--strip-prefix"],
    "XYZ": ["--order", "XYZ"],
}
# Files each peer compares on tests/data/bvh alone (a bare clone): bvhio reads all 17 sources
# right; pybvh refuses two (rows past Frames:, position channels below the root).
AT_LEAST = {"bvhio": 17, "pybvh": 15}


def takes() -> list[Path]:
    """tests/data/bvh, then the whole corpus beside the checkout when there is one (names
    already taken left out)."""
    found = sorted((DATA / "bvh").glob("*.bvh"))
    if (SHARED / "bvh").is_dir():
        names = {p.name for p in found}
        found += sorted(p for p in (SHARED / "bvh").glob("*.bvh") if p.name not in names)
    return found


def run(cli: Path, *args: str) -> subprocess.CompletedProcess:
    return subprocess.run([str(cli), *args], capture_output=True, text=True)


def height_of(cli: Path, path: Path) -> float:
    """The figure's height as `bvhview info` says it ("... it stands H tall")."""
    done = run(cli, "info", str(path))
    assert done.returncode == 0, done.stderr
    found = re.search(r"stands ([0-9.eE+-]+) tall", done.stdout)
    assert found, f"{path.name}: no height in `bvhview info`:\n{done.stdout}"
    return float(found.group(1))


def our_positions(cli: Path, path: Path, scratch: Path) -> tuple[list[str], int, dict[int, np.ndarray]]:
    """`bvhview positions` of a file: (point names, frame count, {frame: points x 3})."""
    out = scratch / "positions.csv"
    done = run(cli, "positions", str(path), "-q", "-o", str(out))
    assert done.returncode == 0, done.stderr
    names: list[str] = []
    points: dict[int, list[list[float]]] = {}
    with open(out, newline="") as file:
        rows = csv.reader(file)
        assert next(rows) == ["frame", "joint", "x", "y", "z"]
        for frame, name, x, y, z in rows:
            f = int(frame)
            if f == 0:
                names.append(name)
            points.setdefault(f, []).append([float(x), float(y), float(z)])
    return names, len(points), {f: np.array(p) for f, p in points.items()}


def end_sites(path: Path) -> list[bool]:
    """The points of a file bvhview wrote, in file order (ROOT, JOINT, End Site), True for an
    End Site: read from the hierarchy's keywords."""
    ends = []
    for line in path.read_text().splitlines():
        words = line.split()
        if words and words[0] in ("ROOT", "JOINT", "End"):
            ends.append(words[0] == "End")
        elif words and words[0] == "MOTION":
            break
    return ends


def bvhio_read(path: Path, frames: list[int]):
    """bvhio's world positions of every joint at `frames`: (names, End Site flags, frames x
    joints x 3, its frame count). Its hierarchy has no End Sites, so a leaf joint's rotation is
    pybvh's to check. Only the wanted keyframes are turned into its joint hierarchy, as
    readAsHierarchy does with all of them (that is its slow part: seconds on a long take)."""
    import bvhio

    container = bvhio.readAsBvh(str(path))
    for joint, _, _ in container.Root.layout():
        joint.Keyframes = [joint.Keyframes[f] for f in frames]
    root = bvhio.convertBvhToHierarchy(container.Root).loadRestPose(recursive=True)
    joints = [joint for joint, _, _ in root.layout()]
    points = np.empty((len(frames), len(joints), 3))
    for k in range(len(frames)):
        root.loadPose(k)
        for j, joint in enumerate(joints):
            points[k, j] = list(joint.PositionWorld)
    return [j.Name for j in joints], [False] * len(joints), points, container.FrameCount


def pybvh_read(path: Path, frames: list[int]):
    """pybvh's world positions of every node, End Sites included, at `frames`."""
    import pybvh

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # its guesses at the up axis
        take = pybvh.read_bvh_file(path)
        points = np.stack([take.node_positions(f) for f in frames])
    nodes = take.nodes
    return [n.name for n in nodes], [n.is_end_site() for n in nodes], points, take.frame_count


PEERS = {"bvhio": bvhio_read, "pybvh": pybvh_read}


def against_ours(read, path: Path, frames: list[int], ours, ends: list[bool], height: float):
    """A peer's reading of `path` against our points `ours` (frames x points x 3, with End Site
    flags `ends`): (worst error over the height, the worst point's index in `ours`, the peer's
    joint names, its frame count) or, where the peer cannot be compared, the reason as a string.
    A peer gives End Sites (matched with ours by index) or none (its joints matched with ours)."""
    try:
        names, peer_ends, points, frame_count = read(path, frames)
    except Exception as error:  # noqa: BLE001 - the peer refuses the file
        said = str(error).splitlines()[0].replace(f" in file {path}", "").replace(str(path), path.name)
        return f"refused: {type(error).__name__}: {said[:100]}"
    if len(names) == len(ends) and peer_ends == ends:
        rows = list(range(len(ends)))
    elif not any(peer_ends) and len(names) == ends.count(False):
        rows = [i for i, end in enumerate(ends) if not end]
    else:
        return f"reads {len(names)} points ({sum(peer_ends)} End Sites), bvhview {len(ends)} ({sum(ends)})"
    errors = np.abs(points - ours[:, rows]).max(axis=(0, 2)) / height
    worst = int(errors.argmax())
    joints = [n for n, end in zip(names, peer_ends) if not end]
    return float(errors[worst]), rows[worst], joints, frame_count


def test_peers_read_the_canonical_layout_as_they_read_the_source(cli, tmp_path):
    pytest.importorskip("bvhio")
    pytest.importorskip("pybvh")
    compared = {peer: [] for peer in PEERS}
    outputs = {peer: 0 for peer in PEERS}
    worst = {peer: (0.0, "") for peer in PEERS}
    skipped: dict[str, list[str]] = {peer: [] for peer in PEERS}
    refused: list[str] = []  # --channels root6,rot3 refuses a moving position channel below the root
    beyond: dict[str, list[str]] = {peer: [] for peer in PEERS}  # outputs read where the source is not
    failures: list[str] = []
    for path in takes():
        scratch = tmp_path / path.stem
        scratch.mkdir()
        height = height_of(cli, path)
        names, frame_count, by_frame = our_positions(cli, path, scratch)
        frames = sorted({f for f in (0, 1, frame_count // 2, frame_count - 1) if 0 <= f < frame_count})
        ours = np.stack([by_frame[f] for f in frames])
        written = {}
        for label, options in RUNS.items():
            out = scratch / f"{label}.bvh"
            done = run(cli, "convert", str(path), "-q", "-o", str(out), *options)
            if done.returncode == 2 and "position channels that move" in done.stderr:
                assert "--channels" in options, path.name
                refused.append(path.name)
                continue
            assert done.returncode == 0, f"{path.name} {label}: {done.stderr}"
            written[label] = out
        # The tree is kept: the source's points (End Sites as `<parent>_End`) in its order.
        (ends, *others) = [end_sites(out) for out in written.values()]
        assert all(other == ends for other in others), path.name
        assert len(ends) == len(names), path.name
        assert all(name.endswith("_End") for name, end in zip(names, ends) if end), path.name
        for peer, read in PEERS.items():
            source = against_ours(read, path, frames, ours, ends, height)
            if isinstance(source, str):
                reason = source
            elif source[3] != frame_count:
                reason = f"reads {source[3]} frames, bvhview {frame_count}"
            elif source[2] != [n for n, end in zip(names, ends) if not end]:
                reason = "reads other joint names"
            elif source[0] > TOLERANCE:
                reason = f"differs from bvhview by {source[0]:.2g} of the height at {names[source[1]]}"
            else:
                reason = None
            if reason is not None:
                skipped[peer].append(f"{path.name} ({reason})")
                # Informational: how the peer does on the outputs of a source it cannot read.
                for label, out in written.items():
                    output = against_ours(read, out, frames, ours, ends, height)
                    said = output if isinstance(output, str) else f"within {output[0]:.2g}"
                    beyond[peer].append(f"{path.name} {label}: {said}")
                continue
            for label, out in written.items():
                output = against_ours(read, out, frames, ours, ends, height)
                where = f"{path.name} {label}"
                if isinstance(output, str):
                    failures.append(f"{peer} reads the source of {where} but {output}")
                    continue
                error, point, joints, frames_read = output
                if "--strip-prefix" not in RUNS[label] and joints != source[2]:
                    failures.append(f"{peer} reads other joint names in {where}")
                if not all(mine.endswith(its) for mine, its in zip(source[2], joints)):
                    failures.append(f"{peer} reads names in {where} that are not the source's without a prefix")
                if frames_read != frame_count:
                    failures.append(f"{peer} reads {frames_read} frames in {where}, the source {frame_count}")
                if error > TOLERANCE:
                    failures.append(f"{peer}: {where} is {error:.3g} of the height off at {names[point]}")
                outputs[peer] += 1
                if error >= worst[peer][0]:
                    worst[peer] = (error, f"{where} at {names[point]}")
            compared[peer].append(path.name)
    print()
    print(f"--channels root6,rot3 refused (position channels that move below the root): "
          f"{len(refused)}: {', '.join(refused) or 'none'}")
    for peer in PEERS:
        error, where = worst[peer]
        print(f"{peer}: {len(compared[peer])} files compared ({outputs[peer]} outputs), worst error "
              f"{error:.2g} of the height ({where}); skipped {len(skipped[peer])}: "
              f"{'; '.join(skipped[peer]) or 'none'}; outputs of skipped sources: "
              f"{'; '.join(beyond[peer]) or 'none'}")
    assert not failures, "\n".join(failures)
    for peer, least in AT_LEAST.items():
        assert len(compared[peer]) >= least, (peer, compared[peer])
