"""What the tests share: where the repository's data is, the Rust CLI, and plain readers of its
output and of BVH rows that owe nothing to bvhview."""

import csv
import io
import os
import shutil
import subprocess
from pathlib import Path

import numpy as np
import pytest

REPO = Path(__file__).resolve().parents[2]
DATA = REPO / "tests" / "data"
# SMPL's 22 body joints in SMPL's order, by the built-in smpl22's names.
SMPL22_ORDER = ["pelvis", "left_hip", "right_hip", "spine1", "left_knee", "right_knee", "spine2",
                "left_ankle", "right_ankle", "spine3", "left_foot", "right_foot", "neck",
                "left_collar", "right_collar", "head", "left_shoulder", "right_shoulder",
                "left_elbow", "right_elbow", "left_wrist", "right_wrist"]
EDGE = REPO / "tests" / "edge"
# The whole corpus beside the checkout, as the Rust tests find it (CI has it).
SHARED = REPO.parent / "shared" / "data"


def whole_corpus_or_skip() -> Path:
    if not SHARED.is_dir():
        pytest.skip(f"needs {SHARED} (the whole corpus beside the checkout)")
    return SHARED


def files(folder: Path, extension: str) -> list[Path]:
    found = sorted(p for p in folder.iterdir() if p.suffix == extension)
    assert found, f"no {extension} files in {folder}"
    return found


def _find_cli() -> Path:
    """The bvhview binary: $BVHVIEW_CLI, else the newest build under the target folder, else one
    built now."""
    if os.environ.get("BVHVIEW_CLI"):
        return Path(os.environ["BVHVIEW_CLI"])
    target = Path(os.environ.get("CARGO_TARGET_DIR", REPO / "target"))
    built = [target / kind / "bvhview" for kind in ("release", "debug")]
    built = [p for p in built if p.is_file()]
    if built:
        return max(built, key=lambda p: p.stat().st_mtime)
    cargo = shutil.which("cargo")
    if cargo is None:
        pytest.fail("no bvhview binary and no cargo to build one: set BVHVIEW_CLI")
    subprocess.run([cargo, "build", "--release", "--locked", "--bin", "bvhview"], cwd=REPO, check=True)
    return target / "release" / "bvhview"


@pytest.fixture(scope="session")
def cli() -> Path:
    return _find_cli()


class CliFailed(Exception):
    """The CLI refused the input; the message is its one line without the `bvhview: ` prefix."""


def cli_positions(cli: Path, path: Path, *extra: str) -> tuple[list[str], np.ndarray]:
    """The CLI's `positions --format csv` as (point names, frames x points x 3 float32)."""
    run = subprocess.run(
        [str(cli), "positions", str(path), "--format", "csv", *extra],
        capture_output=True,
    )
    if run.returncode != 0:
        raise CliFailed(run.stderr.decode().strip().removeprefix("bvhview: "))
    rows = csv.reader(io.StringIO(run.stdout.decode()))
    assert next(rows) == ["frame", "joint", "x", "y", "z"]
    names: list[str] = []
    frames: list[int] = []
    points: list[list[float]] = []
    for frame, name, x, y, z in rows:
        frames.append(int(frame))
        if int(frame) == frames[0]:
            names.append(name)
        points.append([float(x), float(y), float(z)])
    array = np.array(points, dtype=np.float32)
    return names, array.reshape(-1, len(names), 3)


def plain_bvh_rows(path: Path) -> tuple[int, float, list[list[float]]]:
    """(Frames, Frame Time, the first Frames rows) of a BVH file, read with nothing but str and
    float: any line end, whitespace between numbers, blank lines skipped."""
    lines = path.read_bytes().decode("utf-8-sig").splitlines()
    start = next(i for i, line in enumerate(lines) if line.strip() == "MOTION")
    frames_line, time_line, *rows_lines = [line for line in lines[start + 1 :] if line.strip()]
    frames = int(frames_line.split(":")[1])
    frame_time = float(time_line.split(":")[1])
    rows = [[float(word) for word in line.split()] for line in rows_lines]
    return frames, frame_time, rows[:frames]
