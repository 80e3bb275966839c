"""Stubs of the native module; `bvhview` re-exports every name."""

import os
import pathlib
from typing import Any, Literal, Sequence, Tuple, Union, final

import numpy as np
import numpy.typing as npt

__all__ = [
    "load",
    "load_many",
    "metrics",
    "load_character",
    "list_takes",
    "humanml3d_features",
    "Character",
    "Motion",
    "ParseError",
    "__version__",
    "_from_state",
    "_compile_dataset",
    "_dataset_manifest",
    "_merge_datasets",
    "_open_dataset",
    "_dataset_motion",
]

# Names of the stubs alone (the leading underscore says they are not in the module).
_PathLike = Union[str, os.PathLike[str]]
# None for every frame, one frame (negative counts from the end), a slice, or frame numbers.
_Frames = Union[None, int, slice, Sequence[int], npt.NDArray[np.integer]]
_OffsetMode = Literal["replace", "add"]

class ParseError(ValueError):
    """A malformed file: `str(error)` is `path:line:column: message`."""

    path: str
    line: int
    column: int
    message: str

@final
class Motion:
    """A loaded take: skeleton, MOTION values, forward kinematics. Immutable."""

    @property
    def path(self) -> str: ...
    @property
    def motion_path(self) -> str | None: ...
    @property
    def retarget_check(self) -> dict[str, Any] | None:
        """What the retarget that made this take measured it against its source: hips and
        shoulders (widths in legs' lengths, turn in degrees, or None), bones_median and
        bones_p99 (degrees), path, floor, line, refusal. None when no retarget made it."""
    @property
    def offset_mode(self) -> _OffsetMode: ...
    @property
    def joint_names(self) -> list[str]:
        """Every joint in file order, End Sites as `<parent>_End`."""
    def index(self, name: str) -> int:
        """The index of the joint named `name` in `joint_names`; ValueError if none."""
    def children(self, index: int) -> list[int]:
        """The indices of a joint's children, in file order."""
    @property
    def parents(self) -> npt.NDArray[np.int32]:
        """Parent of each joint, -1 for a root."""
    @property
    def end_sites(self) -> npt.NDArray[np.bool_]:
        """True for the End Sites."""
    @property
    def offsets(self) -> npt.NDArray[np.float32]:
        """joints x 3."""
    @property
    def channels(self) -> list[list[str]]:
        """Each joint's channel names in file order."""
    @property
    def rotation_orders(self) -> list[str | None]:
        """Each joint's rotation axes in file order ("ZXY"), or None."""
    @property
    def frame_time(self) -> float: ...
    @property
    def fps(self) -> float | None:
        """1 / frame_time, or None when the Frame Time is not above 0."""
    @property
    def duration(self) -> float:
        """Seconds: frames x frame_time."""
    @property
    def up_axis(self) -> Literal["y", "z"]:
        """The up axis guessed from the motion, as `bvhview info` prints it."""
    @property
    def units(self) -> str:
        """The units guessed from the motion (or stated by an ASF): "centimetres", …"""
    @property
    def metres_per_unit(self) -> float:
        """Metres per unit of the file's lengths, by `units`."""
    @property
    def frame_count(self) -> int: ...
    @property
    def channel_count(self) -> int: ...
    @property
    def warnings(self) -> list[str]:
        """What the CLI warns of: the loader's warnings and the offset-mode guess."""
    @property
    def values(self) -> npt.NDArray[np.float32]:
        """frames x channels, a read-only view of the loaded data (no copy)."""
    @property
    def point_names(self) -> list[str]:
        """The CLI's names for the exported points (End Sites as `<parent>_End`)."""
    @property
    def point_joints(self) -> npt.NDArray[np.int32]:
        """The joint of each point: `positions()[:, point_joints]` is the CLI's export."""
    @property
    def channel_names(self) -> list[str]:
        """One per column of `values`: `Hips_Xposition`, …"""
    @property
    def first_channels(self) -> npt.NDArray[np.int32]:
        """Each joint's first column in `values`, -1 for a joint without channels."""
    def local_matrices(self, frames: _Frames = None) -> npt.NDArray[np.float32]:
        """frames x joints x 4 x 4 local transforms (`T · R`), [row, column]; one int for
        frames: joints x 4 x 4."""
    def local_rotations(
        self, frames: _Frames = None, kind: Literal["quat", "matrix", "6d", "euler", "axis_angle"] = "quat"
    ) -> npt.NDArray[np.float32]:
        """Local rotations: quat (w, x, y, z), matrix 3x3, 6d (first two columns), euler (the
        rotation channels in file order, degrees); one int for frames: no frame axis."""
    def root_translations(self, frames: _Frames = None) -> npt.NDArray[np.float32]:
        """frames x 3 (3 for one int): the first root's translation."""
    def positions(self, frames: _Frames = None) -> npt.NDArray[np.float32]:
        """frames x joints x 3 world positions (joints x 3 for one int, as numpy's a[i]); a
        take without frames has its rest pose."""
    def world_matrices(self, frames: _Frames = None) -> npt.NDArray[np.float32]:
        """frames x joints x 4 x 4 world matrices, [row, column], translation in column 3
        (joints x 4 x 4 for one int)."""
    def trim(self, start: int | None = None, stop: int | None = None) -> Motion:
        """Frames start to stop (stop left out, negatives from the end): `convert --frames`."""
    def resample(self, fps: float) -> Motion:
        """The take at any rate from 0.01 to 1000 fps: `convert --fps`. The file's own rate
        (within 1e-4) keeps every frame and a whole fraction of it (60 to 30) every k-th, bit
        for bit; other rates slerp."""
    def scale(self, factor: float) -> Motion:
        """Every length times factor: `convert --scale`."""
    def mirror(
        self,
        names: dict[str, str] | str | os.PathLike[str] | None = None,
        *,
        rename: bool = False,
    ) -> Motion:
        """The mirror image (`convert --mirror`): left and right joints swap their motion,
        names and topology kept; counterparts as `mirror_names` guesses them, `names` (joint
        to counterpart, or a map file's path as `--mirror-names FILE` reads it) over the guess. rename=True (`--mirror-rename`): each joint reflected
        where it is and the names exchanged instead (`names` gives the new names)."""
    def retarget(
        self,
        target: Motion | str | os.PathLike[str],
        names: dict[str, str] | str | os.PathLike[str] | None = None,
        *,
        any_body: bool = False,
        force: bool = False,
    ) -> Motion:
        """This take's motion on another skeleton: `bvhview retarget --onto`. `target`: a Motion,
        a built-in skeleton's name ("smpl22") or a file; `names` overrides the guessed map
        ({source joint: target joint}; "" leaves a source joint out), or is a map file's path
        (`--map FILE`, `[skeleton.FINGERPRINT]` sections too). A body that does not stand on two
        legs is refused onto one that does unless `any_body`; a result whose check against its
        source finds a side crossed or a width collapsed is refused unless `force` (kept with a
        UserWarning). The result's `retarget_check` holds the check."""
    def retarget_map(self, target: Motion | str | os.PathLike[str]) -> dict[str, str]:
        """The map retarget(target) guesses: {source joint: target joint}."""
    @property
    def mirror_names(self) -> dict[str, str]:
        """The counterparts mirror() swaps: each sided joint's name with its counterpart's."""
    def canonical(
        self,
        *,
        channels: Literal["root6,rot3"] | None = None,
        order: str | None = None,
        strip_prefix: bool = False,
        names: str | None = None,
        rest: Literal["tpose"] | None = None,
    ) -> Motion:
        """One channel layout, one Euler order, names without prefixes or of a family
        (`convert --channels root6,rot3 --order ORDER --strip-prefix --names smpl22`); world
        positions kept."""
    def to_up(self, axis: Literal["y", "z", "x", "-y", "-z", "-x"]) -> Motion:
        """Turned to stand along axis from the guessed up axis: `convert --out-up`."""
    def in_place(self) -> Motion:
        """The root kept over its place along the floor: `convert --in-place`."""
    def ground(self) -> Motion:
        """The lowest point of the soles (each ankle and what is below it) moved to 0:
        `convert --ground`."""
    def in_units(self, units: str | float) -> Motion:
        """Every length scaled from the take's own units to these ("mm", "cm", "m", "in", "ft"
        or metres per unit): `convert --out-units`; positions() then come out in them."""
    def smooth(self, hz: float) -> Motion:
        """Jitter smoothed: a zero-phase low-pass at hz (below half the frame rate) on every
        position channel and joint rotation: `convert --smooth`."""
    def lock_feet(self) -> Motion:
        """Each planted foot held where it landed (two-bone IK on thigh and shin): `convert
        --lock-feet`."""
    def to_dataframe(self, frames: _Frames = None) -> Any:
        """The values as a pandas DataFrame: a row per frame (index "frame"), a column per
        channel (`channel_names`). Needs pandas."""
    @staticmethod
    def from_arrays(
        template: Motion,
        rotations: npt.ArrayLike,
        root_translations: npt.ArrayLike | None = None,
        fps: float | None = None,
        kind: Literal["quat", "matrix", "6d", "euler", "axis_angle"] | None = None,
    ) -> Motion:
        """A take on template's skeleton from local rotations (as `local_rotations` gives them,
        the kind told by their shape) and the first root's translations; save() writes it."""
    @staticmethod
    def from_positions(
        positions: npt.ArrayLike,
        skeleton: Motion | str | os.PathLike[str],
        *,
        joints: list[str] | str | None = None,
        fps: float,
        up: Literal["y", "z", "x", "-y", "-z", "-x"] | None = None,
        smooth: float | None = None,
        layout: str | None = None,
        min_confidence: float = 0.3,
    ) -> Motion:
        """Joint positions (frames x joints x 3) as a take on skeleton (a Motion, "smpl22" or a
        file's path): `bvhview solve`. joints: their names in order, or "smpl22"/"humanml3d";
        22 joints without it are read in SMPL's order."""
    @staticmethod
    def from_humanml3d(
        vectors: npt.ArrayLike,
        skeleton: Motion | str | os.PathLike[str] | None = None,
        *,
        fps: float = 20.0,
    ) -> Motion:
        """A take from HumanML3D's 263-value vectors (frames x 263): `bvhview solve --from
        humanml3d`. skeleton: default "smpl22"."""
    def save(self, path: _PathLike, *, units: str | float | None = None) -> None:
        """Writes BVH (.bvh), glTF (.glb binary, .gltf text), FBX (.fbx, 7.4 binary in
        centimetres) or AMASS's .npz (a take on a SMPL-family skeleton), as `bvhview convert`
        does; `units` writes in those units instead."""
    def __len__(self) -> int: ...

__version__: str

@final
class Character:
    """A skinned mesh read from an FBX or glTF file with the skeleton it is bound to. Immutable."""

    @property
    def path(self) -> str:
        """The file read."""
    @property
    def motion(self) -> Motion:
        """The file's own take on the character's skeleton."""
    @property
    def vertex_count(self) -> int:
        """How many vertices the mesh has."""
    @property
    def triangles(self) -> npt.NDArray[np.uint32]:
        """Triangles × 3 vertex indices."""
    def dress(self, take: Motion, *, any_body: bool = False, force: bool = False) -> Motion:
        """`take` retargeted onto the character's skeleton by role, checked as `retarget`
        checks it (`any_body`, `force` as there); the result's `retarget_check` holds the check."""
    def vertices(
        self, take: Motion | None = None, frames: _Frames | None = None
    ) -> npt.NDArray[np.float32]:
        """Skinned vertices, frames × vertices × 3 (vertices × 3 for one int), metres, Y up.
        `take` (default: the character's own) must be on the character's skeleton."""
    def save(self, path: _PathLike, take: Motion | None = None) -> None:
        """Writes `take` (default: the character's own) with the mesh bound to it: glTF
        (.glb, .gltf) or FBX (.fbx), as `bvhview convert --character` does."""

def load_character(
    path: _PathLike, *, take: str | int | None = None, betas: Sequence[float] | None = None
) -> Character:
    """A character: an .fbx, .glb or .gltf file with a skinned mesh, or a SMPL-family model
    file (.npz) of shape `betas`."""

def load(
    path: _PathLike,
    motion: _PathLike | None = None,
    offset_mode: _OffsetMode = "replace",
    frame_time: float | None = None,
    *,
    take: str | int | None = None,
    units: str | float | None = None,
    up: Literal["y", "z", "x", "-y", "-z", "-x"] | None = None,
    body_model: _PathLike | None = None,
) -> Motion:
    """A take: a .bvh, .fbx, .gltf, .glb or AMASS .npz file, or an .asf skeleton with `motion` its .amc
    take, or a built-in skeleton by name ("smpl22"). `take` picks one take of an FBX or glTF
    file that holds several (its name, or its index as `bvhview info FILE` lists them; default:
    the first). `units` ("mm", "cm", "m", "in", "ft" or metres per unit) and `up` ("y", "z",
    "x", "-y", "-z" or "-x"; the last four turn the take to stand along y as it is read, with a
    warning in `warnings`) over the guess. `body_model`: the user's SMPL-family model file (or a folder of them) an
    AMASS file's body is read with."""

def metrics(
    take: Motion,
    *,
    floor: float | None = None,
    contact_height: float = 0.05,
    skate_speed: float = 0.5,
    window: int = 5,
    float_tolerance: float = 0.005,
) -> dict[str, Any]:
    """How plausible a take is, as `bvhview metrics` measures it: GMD's skating ratio,
    PhysDiff's penetrate/float/skate (mm), jitter, bone drift, the floor and each foot."""

def load_many(
    paths: _PathLike | Sequence[Union[_PathLike, Tuple[_PathLike, _PathLike]]],
    offset_mode: _OffsetMode = "replace",
    frame_time: float | None = None,
    errors: Literal["raise", "return"] = "raise",
    *,
    units: str | float | None = None,
    up: Literal["y", "z", "x", "-y", "-z", "-x"] | None = None,
) -> list[Motion]:
    """Every path (or (asf, amc) pair) loaded on all cores, in order; a folder: every BVH file
    and ASF/AMC pair under it, in path order. With errors="return", a failed entry is its
    exception instead. `units` and `up` say what every take is, as load()'s do."""

def _from_state(state: tuple[object, ...]) -> Motion:
    """A take from its pickled state (what `pickle` calls; not for calling directly)."""

def list_takes(folder: _PathLike) -> list[tuple[pathlib.Path, pathlib.Path | None]]:
    """Every take under folder in path order, as (path, motion) relative to it."""

def _compile_dataset(
    folder: _PathLike,
    out: _PathLike,
    fps: float | None = None,
    rotations: str = "6d",
    root_relative: bool = False,
    feet: Sequence[str] | None = None,
    contact_height: float = 0.05,
    contact_speed: float = 0.5,
    takes: Sequence[tuple[_PathLike, _PathLike | None]] | None = None,
    piece: tuple[int, int] | None = None,
    threads: int | None = None,
    onto: str | None = None,
    ground: bool = False,
    quat_continuous: bool = False,
    names: dict[str, str] | str | os.PathLike[str] | None = None,
    lock_feet: bool = False,
    features: str = "arrays",
    any_body: bool = False,
    force: bool = False,
    units: str | float | None = None,
    up: str | None = None,
    out_units: str | float | None = None,
) -> tuple[int, int, int, list[tuple[str, str | None, str]]]:
    """The native half of bvhview.compile_dataset: (clips, frames, groups, skipped takes as
    (path, motion, reason))."""

def _merge_datasets(
    pieces: Sequence[_PathLike], out: _PathLike, join: str = "pieces"
) -> tuple[int, int, int, int]:
    """The native half of bvhview.merge_datasets: (clips, frames, groups, skipped)."""

def humanml3d_features(
    positions: npt.ArrayLike,
) -> tuple[npt.NDArray[np.float32], npt.NDArray[np.float32]]:
    """Joint positions (frames x 22 x 3: SMPL's order, metres, y up, 20 fps) as HumanML3D's
    pipeline turns them into its vectors: ((frames - 1) x 263 vectors, the (frames - 1) x 22 x 3
    positions they stand for)."""

def _dataset_manifest(path: _PathLike) -> str:
    """The manifest of the dataset at path as JSON, the dataset checked first (either layout)."""

def _open_dataset(
    path: _PathLike,
) -> tuple[str, list[list[tuple[str, int, str, list[int]]]], list[list[int]]]:
    """The dataset checked whole: (manifest JSON, per group its arrays as (name, descriptor,
    dtype, shape), per group its clips' starts and end)."""

def _dataset_motion(
    path: _PathLike,
    group: int,
    rotations: npt.ArrayLike,
    kind: str,
    translations: npt.ArrayLike | None = None,
    root_translations: npt.ArrayLike | None = None,
    clip: int | None = None,
    fps: float | None = None,
) -> Motion:
    """Arrays in a dataset group's layout as a take on its skeleton."""
