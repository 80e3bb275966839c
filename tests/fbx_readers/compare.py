#!/usr/bin/env python3
"""What an FBX reader read (check_assimp's, check_three.mjs's or check_blender.py's JSON) against what bvhview wrote.

    compare.py --hierarchy TAKE.bvh --positions TAKE.csv --info TAKE.info --take NAME \
        [--bone-ends] DUMP.json [DUMP.json ...]

bvhview's side, all from the source take (not from the FBX):
  --hierarchy  the take converted to BVH (`bvhview convert IN -o x.bvh`): the joints and End
               Sites in the order FBX out writes them, each one's parent, and which joints carry
               channels (FBX out writes curves for those and only those);
  --positions  `bvhview positions IN`: every joint's world position per frame, in the take's units;
  --info       `bvhview info IN`: frames, frame time, units, height and up axis;
  --take       the take's name, as the FBX states it (the stack's name);
  --bone-ends  the take is ASF/AMC: `positions` gives each bone's end, which is where the
               bone's child joints (or its End Site) start.

Per reader it checks: the file loads, with no warning or error; the node tree is the take's (names as the
reader spells them, parents); one animation named after the take, channels on exactly the joints
with channels, every frame keyed, its duration (frames - 1) x frame time; and every joint's world
position at each frame in the dump within the tolerance of the figure's height, in metres (the
reader's lengths times the file's UnitScaleFactor, centimetres). The file is Y up whatever the take
(FBX out turns a Z-up take as it writes it, (x, y, z) -> (x, z, -y)); Blender's world is Z up: it
turns the file (x, y, z) -> (x, -z, y), and the positions are compared turned the same way.

Prints one line per reader, `READER: worst E of the height (frame F, JOINT)` or `READER: FAIL: ...`,
and exits with the number of readers that failed.
"""

import argparse
import csv
import json
import math
import re
import sys

UNITS = {
    "metres": 1.0,
    "decimetres": 0.1,
    "centimetres": 0.01,
    "millimetres": 0.001,
    "inches": 0.0254,
    "CMU units (1/0.45 inch)": 0.0254 / 0.45,
}


def read_hierarchy(path):
    """(name, parent index, has channels) per joint and End Site, in file order."""
    joints, stack = [], []
    pending = None
    with open(path, encoding="utf-8") as f:
        for raw in f:
            line = raw.strip()
            if line.startswith("MOTION"):
                break
            if line.startswith(("ROOT ", "JOINT ")):
                pending = line.split(None, 1)[1]
            elif line.startswith("End Site"):
                pending = joints[stack[-1]][0] + "_End"
            elif line == "{":
                parent = stack[-1] if stack else -1
                joints.append([pending, parent, False])
                stack.append(len(joints) - 1)
            elif line == "}":
                stack.pop()
            elif line.startswith("CHANNELS"):
                joints[stack[-1]][2] = int(line.split()[1]) > 0
    return joints


def read_info(path):
    text = open(path, encoding="utf-8").read()

    def field(name):
        found = re.search(rf"^{name}:\s+(.*)$", text, re.M)
        if not found:
            raise SystemExit(f"compare.py: no '{name}:' in {path}")
        return found.group(1)

    units_line = field("units")
    unit = next((u for u in sorted(UNITS, key=len, reverse=True) if units_line.startswith(u)), None)
    if unit is None:
        raise SystemExit(f"compare.py: unknown units '{units_line}'")
    height = float(re.search(r"stands ([0-9.e+-]+) tall", units_line).group(1))
    return {
        "frames": int(field("frames").split()[0]),
        "frame_time": float(field("frame time").split()[0]),
        "metres": UNITS[unit],
        "height": height * UNITS[unit],
        "up": field("up axis").split()[0],
    }


def read_positions(path, frames):
    """{frame: [(name, (x, y, z))]} for the frames asked."""
    rows = {f: [] for f in frames}
    with open(path, encoding="utf-8", newline="") as f:
        for row in csv.DictReader(f):
            frame = int(row["frame"])
            if frame in rows:
                rows[frame].append((row["joint"], tuple(float(row[k]) for k in "xyz")))
    return rows


def three_name(name):
    """three.js's PropertyBinding.sanitizeNodeName: whitespace to _, no [ ] . : /."""
    return re.sub(r"[\[\].:/]", "", re.sub(r"\s", "_", name))


def check(dump, take, args):
    """Problems found (a list of strings), and the worst error over the height with where."""
    three = dump["reader"].startswith("three")
    blender = dump["reader"].startswith("blender")
    problems = []
    if "error" in dump:
        return [f"did not load: {dump['error']}"], None
    # FBX out is Y up whatever the take (a Z-up take is turned as it is written): no reader has a
    # reason to say anything (three.js's note on a Z-up file included).
    for message in dump["messages"]:
        problems.append(f"said: {message}")

    # The node tree: the reader's root (assimp's RootNode, three.js's Group, Blender's Armature
    # object: Blender makes the joints bones of an armature object it adds for the scene's root,
    # itself no node of the file) left out, and
    # assimp's helper nodes for pivots (none expected: the file has none).
    nodes = dump["nodes"]
    kept, where = [], {}
    for i, (name, parent) in enumerate(nodes):
        if parent == -1 or "$AssimpFbx$" in name:
            if "$AssimpFbx$" in name:
                problems.append(f"helper node {name}")
            continue
        while parent != -1 and (nodes[parent][1] == -1 or "$AssimpFbx$" in nodes[parent][0]):
            parent = -1 if nodes[parent][1] == -1 else nodes[parent][1]
        where[i] = len(kept)
        kept.append((i, name, where.get(parent, -1)))
    joints = take["joints"]
    if len(kept) != len(joints):
        problems.append(f"{len(kept)} nodes, {len(joints)} joints and End Sites written")
        return problems, None
    seen = {}
    for (_, name, parent), (want, want_parent, _) in zip(kept, joints):
        spelled = three_name(want) if three else want
        seen[spelled] = seen.get(spelled, -1) + 1
        # assimp numbers a name met again (Foot_End, Foot_End001), Blender too (Foot_End.001).
        again = f".{seen[spelled]:03d}" if blender else f"{seen[spelled]:03d}"
        ok = name == spelled or (not three and seen[spelled] and name == spelled + again)
        if not ok:
            problems.append(f"node {name!r} where {want!r} was written")
        if parent != want_parent:
            problems.append(f"{want} under node {parent}, written under {want_parent}")

    # The animation.
    info = take["info"]
    frames = info["frames"]
    animated = {three_name(n) if three else n for n, _, has in joints if has}
    animations = dump["animations"]
    if frames and len(animations) != 1:
        problems.append(f"{len(animations)} animations, 1 written")
    if animations:
        animation = animations[0]
        if animation["name"] != args.take:
            problems.append(f"animation {animation['name']!r}, written {args.take!r}")
        channels = {}
        for channel in animation["channels"]:
            node = channel["node"].rsplit(".", 1)[0] if three else channel["node"]
            keys = channel["keys"] if three else max(channel["position_keys"], channel["rotation_keys"])
            channels[node] = max(channels.get(node, 0), keys)
        if set(channels) != animated:
            missing, extra = sorted(animated - set(channels)), sorted(set(channels) - animated)
            problems.append(f"channels: missing {missing[:5]}, not written {extra[:5]}")
        # Both add keys between two angles 180 degrees or more apart (none in FBX out's curves).
        short = [n for n, k in channels.items() if k < frames]
        if short:
            problems.append(f"{len(short)} channels not keyed at the {frames} frames ({short[:3]})")
        seconds = animation["duration"] / (animation["ticks_per_second"] or 1)
        want = (frames - 1) * info["frame_time"]
        if abs(seconds - want) > 1e-4 * max(want, info["frame_time"]):
            problems.append(f"duration {seconds} s, written {want} s")

    # Joint positions, in metres.
    scale = dump.get("unit_scale_factor") or 0
    if scale <= 0:
        problems.append(f"UnitScaleFactor {dump.get('unit_scale_factor')}")
        scale = 1
    to_metres = scale * 0.01
    names = [n for n, _, _ in joints]
    first_child = {}
    for index, (_, parent, _) in enumerate(joints):
        first_child.setdefault(parent, index)
    worst, at = 0.0, None
    for entry in dump["frames"]:
        frame = entry["frame"]
        got = [entry["positions"][i] for i, _, _ in kept]
        rows = take["positions"][frame]
        for k, (name, p) in enumerate(rows):
            if args.bone_ends and k > 0:
                parent = names.index(name)
                j = first_child.get(parent)
                if j is None:
                    problems.append(f"{name}: no child joint or End Site to end the bone")
                    continue
            else:
                j = k
            want = [v * info["metres"] for v in p]
            if info["up"] == "z":
                want = [want[0], want[2], -want[1]]  # FBX out turned the take Y up
            if blender:
                want = [want[0], -want[2], want[1]]  # Blender turns the Y-up file Z up
            have = [v * to_metres for v in got[j]]
            error = math.dist(want, have) / info["height"]
            if not error <= worst:
                worst, at = error, f"frame {frame}, {name}"
    if worst > args.tolerance:
        problems.append(f"positions {worst:.3g} of the height off at {at}")
    return problems, (worst, at)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--hierarchy", required=True)
    parser.add_argument("--positions", required=True)
    parser.add_argument("--info", required=True)
    parser.add_argument("--take", required=True)
    parser.add_argument("--bone-ends", action="store_true")
    parser.add_argument("--tolerance", type=float, default=1e-4)
    parser.add_argument("dumps", nargs="+")
    args = parser.parse_args()

    joints = read_hierarchy(args.hierarchy)
    info = read_info(args.info)
    dumps = []
    for path in args.dumps:
        try:
            dumps.append(json.load(open(path, encoding="utf-8")))
        except (OSError, ValueError) as error:
            dumps.append({"reader": path, "messages": [], "error": f"no readable output ({error})"})
    frames = sorted({f["frame"] for d in dumps for f in d.get("frames", [])})
    positions = read_positions(args.positions, frames)
    if not args.bone_ends and frames:
        # Joints and End Sites as `positions` names them, which is how FBX out names them.
        rows = positions[frames[0]]
        if len(rows) != len(joints):
            print(f"compare.py: {len(rows)} positions a frame, {len(joints)} joints in {args.hierarchy}")
            return len(dumps)
        for joint, (name, _) in zip(joints, rows):
            joint[0] = name
    take = {"joints": joints, "info": info, "positions": positions}
    failed = 0
    for dump in dumps:
        reader = dump["reader"].split()[0]
        problems, result = check(dump, take, args)
        if problems:
            failed += 1
            print(f"{reader}: FAIL: " + "; ".join(problems[:6]) + ("; …" if len(problems) > 6 else ""))
        else:
            worst, at = result
            print(f"{reader}: worst {worst:.2e} of the height ({at})")
    return failed


if __name__ == "__main__":
    sys.exit(main())
