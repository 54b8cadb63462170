"""Embree 4's primary-ray throughput on the view of `cargo bench --bench mesh`, for comparison.

The mesh is the same icosphere as `raytree::mesh::generate::icosphere` (the same 12-vertex
icosahedron, each face split into 4 per level, vertices pushed onto the unit sphere); the camera
is `sphere_scene`'s: at (0, 0, 3) looking at the origin (or at (0, 0, D) with `--distance D`),
40 degrees vertical field of view, one ray through each pixel centre. Embree is called through
`embreex` (the Python binding trimesh uses, Embree 4.4), whose `run` loops over the rays with
`rtcIntersect1`, one thread. `cargo run --release --example primary -- LEVEL SIZE D` casts the
same view with raytree.

Not run by CI (it needs packages from PyPI). To reproduce the tables in docs/mesh.md:

    python3 -m venv /tmp/embree && /tmp/embree/bin/pip install embreex numpy
    taskset -c 0 /tmp/embree/bin/python benches/embree.py 8 256 512 1024
    taskset -c 0 /tmp/embree/bin/python benches/embree.py 8 512 --distance 4

Arguments: subdivision level (8: 1,310,720 triangles), image sizes, `--distance D`. With
`--dump FILE` instead of sizes, writes the mesh for benches/embree_native.c (native Embree 3
from C, with its packet calls).
"""

import sys
import time

import numpy as np
from embreex import rtcore_scene
from embreex.mesh_construction import TriangleMesh


def icosphere(level):
    g = (1 + 5**0.5) / 2
    v = np.array(
        [(-1, g, 0), (1, g, 0), (-1, -g, 0), (1, -g, 0), (0, -1, g), (0, 1, g),
         (0, -1, -g), (0, 1, -g), (g, 0, -1), (g, 0, 1), (-g, 0, -1), (-g, 0, 1)],
        float,
    )
    v /= np.linalg.norm(v, axis=1)[:, None]
    f = np.array(
        [(0, 11, 5), (0, 5, 1), (0, 1, 7), (0, 7, 10), (0, 10, 11), (1, 5, 9), (5, 11, 4),
         (11, 10, 2), (10, 7, 6), (7, 1, 8), (3, 9, 4), (3, 4, 2), (3, 2, 6), (3, 6, 8),
         (3, 8, 9), (4, 9, 5), (2, 4, 11), (6, 2, 10), (8, 6, 7), (9, 8, 1)]
    )
    for _ in range(level):
        edges = np.sort(np.concatenate([f[:, [0, 1]], f[:, [1, 2]], f[:, [2, 0]]]), axis=1)
        unique, inverse = np.unique(edges, axis=0, return_inverse=True)
        mid = v[unique[:, 0]] + v[unique[:, 1]]
        mid /= np.linalg.norm(mid, axis=1)[:, None]
        m = inverse.reshape(3, -1).T + len(v)
        v = np.concatenate([v, mid])
        a, b, c = f.T
        ab, bc, ca = m.T
        f = np.concatenate(
            [np.stack(t, 1) for t in ((a, ab, ca), (b, bc, ab), (c, ca, bc), (ab, bc, ca))]
        )
    return v, f


def camera_rays(size, distance=3.0):
    half = np.tan(np.radians(40) / 2)
    ys, xs = np.mgrid[0:size, 0:size]
    u = ((xs + 0.5) / size * 2 - 1) * half
    w = (1 - (ys + 0.5) / size * 2) * half
    d = np.stack([u, w, -np.ones_like(u)], -1).reshape(-1, 3)
    d /= np.linalg.norm(d, axis=1)[:, None]
    o = np.tile(np.array([0, 0, distance], np.float32), (len(d), 1))
    return o, d.astype(np.float32)


def dump(path, v, f):
    """The mesh for benches/embree_native.c: vertex and triangle counts (u32), the vertices
    (f32 triples), the triangles (u32 triples)."""
    with open(path, "wb") as out:
        out.write(np.array([len(v), len(f)], np.uint32).tobytes())
        out.write(v.astype(np.float32).tobytes())
        out.write(f.astype(np.uint32).tobytes())


def main():
    args = sys.argv[1:]
    if "--dump" in args:
        k = args.index("--dump")
        v, f = icosphere(int(args[0]) if k > 0 else 8)
        dump(args[k + 1], v, f)
        return
    distance = 3.0
    if "--distance" in args:
        k = args.index("--distance")
        distance = float(args[k + 1])
        del args[k : k + 2]
    level = int(args[0]) if args else 8
    sizes = [int(s) for s in args[1:]] or [512]
    v, f = icosphere(level)
    scene = rtcore_scene.EmbreeScene()
    TriangleMesh(scene, v[f].astype(np.float32))
    for size in sizes:
        o, d = camera_rays(size, distance)
        scene.run(o, d)  # the first call builds the BVH
        best = float("inf")
        for _ in range(7):
            t = time.perf_counter()
            ids = scene.run(o, d)
            best = min(best, time.perf_counter() - t)
        print(
            f"embree4 {len(f)} triangles {size}x{size} distance {distance}: "
            f"hit {np.mean(ids >= 0):.3f}, "
            f"{best * 1e9 / len(d):.1f} ns/ray, {len(d) / best / 1e6:.2f} M rays/s "
            "(fastest of 7)"
        )


if __name__ == "__main__":
    main()
