#!/usr/bin/env python3
"""The render time of two raytree binaries in one run, as a ratio (issue 28: a restructuring
must keep the speed within 2%). Each case renders with both binaries alternately, REPS times, and
the fastest wall time of each counts (the least disturbed run). Not run by CI.

Usage: benches/speed_ratio.py OLD_BINARY NEW_BINARY [REPS]
"""
import os, subprocess, sys, tempfile, time

CASES = [
    ("classic (Whitted, glass)", "fixtures/classic.json --size 1920x1080 --spp 4"),
    ("diffuse (direct-only path)", "fixtures/diffuse.json --size 1920x1080 --spp 4"),
    ("soft-shadows (area lights)", "fixtures/soft-shadows.json --spp 16"),
    ("glossy (rough lobes)", "fixtures/glossy.json --spp 16"),
    ("cornell-box (path, 16 spp)", "fixtures/cornell-box.json --integrator path --spp 16"),
    ("caustic (path, 64 spp)", "fixtures/caustic.json --integrator path --spp 64"),
]


def run(binary, args, out):
    t0 = time.perf_counter()
    subprocess.run([binary, "render", *args.split(), "-o", out], check=True,
                   stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    return time.perf_counter() - t0


def main():
    old, new = sys.argv[1], sys.argv[2]
    reps = int(sys.argv[3]) if len(sys.argv) > 3 else 5
    os.chdir(os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
    cases = list(CASES)
    if os.path.isdir("../shared/data/meshes"):
        cases.append(("bunny (mesh packets)", "fixtures/mesh/bunny.json"))
    out = os.path.join(tempfile.mkdtemp(), "x.exr")
    print(f"{'case':30} {'old s':>9} {'new s':>9} {'new/old':>8}")
    ratios = []
    for name, args in cases:
        bo = bn = float("inf")
        for _ in range(reps):
            bo = min(bo, run(old, args, out))
            bn = min(bn, run(new, args, out))
        ratios.append(bn / bo)
        print(f"{name:30} {bo:9.3f} {bn:9.3f} {bn / bo:8.3f}", flush=True)
    prod = 1.0
    for r in ratios:
        prod *= r
    print(f"{'geometric mean':30} {'':9} {'':9} {prod ** (1 / len(ratios)):8.3f}")


main()
