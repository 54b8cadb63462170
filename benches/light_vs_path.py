#!/usr/bin/env python3
"""Light tracing and BDPT against path tracing: time to equal error on a region (issue 30).

For each integrator and spp, renders the scene (the binary's own timer: the `time X s` line),
compares a region against a converged path-traced reference (`raytree compare --region`), and
reports RMSE, time and the efficiency 1 / (RMSE^2 time). The ratio of two efficiencies is the
ratio of the times they need to reach the same error (error falls as 1/sqrt(time)). Run:

    python3 benches/light_vs_path.py BINARY SCENE X0,Y0,X1,Y1 [REF_SPP] [SPPS]

e.g. `python3 benches/light_vs_path.py target/release/raytree fixtures/caustic.json
40,108,200,180 2048 16,64,256`. Not run in CI (minutes of rendering; timings need a quiet
machine). Prints a Markdown table.
"""

import re
import subprocess
import sys
import tempfile
from pathlib import Path


def render(binary, scene, integrator, spp, out, seed):
    o = subprocess.run(
        [binary, "render", scene, "--integrator", integrator, "--spp", str(spp),
         "--seed", str(seed), "-o", str(out)],
        capture_output=True, text=True, check=True)
    secs = float(re.search(r"time ([0-9.]+) s", o.stdout + o.stderr).group(1))
    return secs


def rmse(binary, a, b, region):
    o = subprocess.run([binary, "compare", str(a), str(b), "--region", region],
                       capture_output=True, text=True, check=True)
    return float(re.search(r"RMSE ([0-9.eE+-]+)", o.stdout).group(1))


def main():
    binary, scene, region = sys.argv[1], sys.argv[2], sys.argv[3]
    ref_spp = int(sys.argv[4]) if len(sys.argv) > 4 else 2048
    spps = [int(s) for s in (sys.argv[5] if len(sys.argv) > 5 else "16,64,256").split(",")]
    d = Path(tempfile.mkdtemp())
    ref = d / "ref.exr"
    t_ref = render(binary, scene, "path", ref_spp, ref, 7)
    print(f"reference: path at {ref_spp} spp, {t_ref:.1f} s; region {region}\n")
    print("| integrator | spp | time (s) | RMSE (region) | efficiency 1/(RMSE^2 t) | vs path |")
    print("|---|---:|---:|---:|---:|---:|")
    for spp in spps:
        eff = {}
        rows = []
        for integ in ["path", "light", "bdpt"]:
            out = d / f"{integ}-{spp}.exr"
            t = render(binary, scene, integ, spp, out, 1)
            e = rmse(binary, out, ref, region)
            eff[integ] = 1.0 / (e * e * t)
            rows.append((integ, t, e))
        for integ, t, e in rows:
            ratio = eff[integ] / eff["path"]
            print(f"| {integ} | {spp} | {t:.3f} | {e:.4e} | {eff[integ]:.4g} | {ratio:.2f}x |")


if __name__ == "__main__":
    main()
