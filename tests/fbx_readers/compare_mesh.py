#!/usr/bin/env python3
"""A reader's skinned mesh of a character FBX against bvhview's, vertex by vertex.

    compare_mesh.py --vertices WANT.npy --frames F1,F2,… [--tolerance 1e-4] DUMP.json …

WANT.npy: `bvhview positions INPUT --character CHAR --vertices -o WANT.npy`, (frames, vertices,
3) float32, metres, Y up: bvhview's skinning of the take on the character. DUMP.json: what a
reader read (check_blender.py --mesh): it loaded with no warning or error (`messages`), and its
`mesh_file` holds the evaluated mesh at the frames listed, in that order, (len(frames),
vertices, 3) in metres in the reader's world. Blender's world is Z up, so WANT is turned as
Blender turns a Y-up file, (x, y, z) -> (x, -z, y) (the characters are Y up).

The vertices are matched by index: FBX out writes each mesh part's vertices as its control
points, and Blender keeps control points as its vertices, one for one, meshes in the file's
order; the counts must agree, and when they do not the check fails saying both. The tolerance is
1e-4 of the figure's height: the extent of WANT's y over its first frame.

Prints one line per reader, `READER: mesh: worst E of the height (frame F, vertex V)` or
`READER: mesh: FAIL: …`, and exits with the number of readers that failed. Standard library
only (no numpy): a .npy of little-endian float32 or float64 in C order is all it reads.
"""

import argparse
import ast
import json
import math
import struct
import sys


def load_npy(path):
    """(shape, flat list of floats) of a .npy file of '<f4' or '<f8' in C order."""
    with open(path, "rb") as f:
        data = f.read()
    if data[:6] != b"\x93NUMPY":
        raise ValueError(f"{path}: not a .npy file")
    major = data[6]
    if major == 1:
        (size,), start = struct.unpack_from("<H", data, 8), 10
    else:
        (size,), start = struct.unpack_from("<I", data, 8), 12
    header = ast.literal_eval(data[start : start + size].decode("latin-1"))
    if header["fortran_order"] or header["descr"] not in ("<f4", "<f8"):
        raise ValueError(f"{path}: {header['descr']} (Fortran order {header['fortran_order']}), not <f4 or <f8")
    shape = tuple(header["shape"])
    count = math.prod(shape)
    kind = "f" if header["descr"] == "<f4" else "d"
    return shape, struct.unpack_from(f"<{count}{kind}", data, start + size)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--vertices", required=True)
    parser.add_argument("--frames", required=True)
    parser.add_argument("--tolerance", type=float, default=1e-4)
    parser.add_argument("dumps", nargs="+", metavar="DUMP.json")
    args = parser.parse_args()
    (frames_all, count, _), want_all = load_npy(args.vertices)
    frames = [int(f) for f in args.frames.split(",")]
    ys = want_all[1 : count * 3 : 3]
    height = max(ys) - min(ys)
    failed = 0
    for path in args.dumps:
        try:
            dump = json.load(open(path, encoding="utf-8"))
            reader = dump["reader"].split()[0]
        except (OSError, ValueError, KeyError) as error:
            print(f"{path}: mesh: FAIL: no readable output ({error})")
            failed += 1
            continue
        problems = [f"said: {m}" for m in dump.get("messages", [])]
        if "error" in dump:
            problems.append(f"did not load: {dump['error']}")
        else:
            try:
                shape, got = load_npy(dump["mesh_file"])
            except (OSError, ValueError, KeyError) as error:
                problems.append(f"no mesh ({error})")
        if problems:
            print(f"{reader}: mesh: FAIL: " + "; ".join(problems[:6]))
            failed += 1
            continue
        if shape != (len(frames), count, 3):
            print(f"{reader}: mesh: FAIL: {shape[1] if len(shape) == 3 else shape} vertices at "
                  f"{shape[0]} frames, bvhview has {count} at {len(frames)}")
            failed += 1
            continue
        worst, at = 0.0, None
        for k, frame in enumerate(frames):
            for v in range(count):
                x, y, z = want_all[(frame * count + v) * 3 : (frame * count + v) * 3 + 3]
                if reader == "blender":
                    x, y, z = x, -z, y
                have = got[(k * count + v) * 3 : (k * count + v) * 3 + 3]
                error = math.dist((x, y, z), have) / height
                if not error <= worst:
                    worst, at = error, f"frame {frame}, vertex {v}"
        if not worst <= args.tolerance:
            print(f"{reader}: mesh: FAIL: vertices {worst:.3g} of the height off ({at})")
            failed += 1
        else:
            print(f"{reader}: mesh: worst {worst:.2e} of the height ({at})")
    return failed


if __name__ == "__main__":
    sys.exit(main())
