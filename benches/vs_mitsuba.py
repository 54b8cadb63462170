"""Time to equal error: raytree against Mitsuba 3 (`llvm_ad_rgb`) on the same scene, one run.

For each scene the script converts the raytree JSON to a Mitsuba 3 scene (`to_mitsuba`), renders
a reference with Mitsuba's path tracer at high spp (cached beside the output), then renders the
scene with both renderers at increasing spp and reports the relative RMSE against the reference
and the time of each render.

Timing, made fair: Mitsuba's time is `mi.render` plus `dr.eval` of the image, on a scene loaded
beforehand and with its kernels compiled by an untimed 1-spp render (so scene loading, BVH build,
JIT compilation and writing are outside it). raytree's "render s" is the time `raytree render`
prints, which likewise starts after the scene is loaded and its BVH built and stops before the
image is encoded; its "wall s" (process start, JSON, BVH, render, EXR) is shown beside it. The
ratios use the render times. From the two error-vs-seconds curves it interpolates (log-log)
the time each renderer needs to reach the same error, and prints the ratio raytree / Mitsuba.

Only light transport both renderers compute the same way can be compared: the scenes must use
constant colours, `diffuse` (Lambert), `reflectivity` (a mirror without Fresnel: Mitsuba's
`conductor` with `material: none`), `transmissivity` + `ior` (a smooth dielectric with exact
Fresnel: Mitsuba's `dielectric`), `emission` (an area emitter on the outer side), point and
directional lights, a constant background (an environment), spheres, planes (a large
rectangle), quads, triangles and boxes. Ambient, Blinn-Phong `specular`, textures, absorption
and translucent shadows are Whitted's own and refused with the reason. The Whitted integrator
adds no light reflected diffusely, so for `--integrator whitted` a scene must have no diffuse
surface lit by anything but point and directional lights with nothing reflective to see it
(e.g. emitters seen through glass and mirrors): the bench scenes in benches/mitsuba-scenes/ are built
that way.

Not run by CI (it needs PyPI and Debian packages). Set-up and the tables in docs/cost.md:

    apt-get install -y libllvm19 && pip install mitsuba numpy
    export DRJIT_LIBLLVM_PATH=/usr/lib/x86_64-linux-gnu/libLLVM.so.19.1
    cargo build --release
    python3 benches/vs_mitsuba.py benches/mitsuba-scenes/glass-emitters.json --out /tmp/mts

Options: `--integrator whitted|path` (raytree's), `--size WxH`, `--ref-spp N` (Mitsuba's
reference, default 4096), `--raytree-spp 1,4,16,...`, `--mitsuba-spp 4,16,...`,
`--max-depth D` (both), `--raytree ARGS` (extra raytree flags), `--raytree-configs "A;B;..."`
(instead of `--raytree-spp`: one raytree render per semicolon-separated set of flags, e.g.
`"--spp 4;--spp 2 --adaptive 0.1 --max-spp 16"`).
"""

import argparse
import hashlib
import json
import math
import os
import re
import subprocess
import sys
import time

import numpy as np

RAYTREE = os.environ.get("RAYTREE", "target/release/raytree")


class Unsupported(Exception):
    pass


def rgb(v):
    return {"type": "rgb", "value": [float(x) for x in v]}


def nonzero(v):
    return v is not None and any(abs(x) > 0 for x in v)


def const_colour(m, key, name):
    v = m.get(key)
    if v is None:
        return None
    if isinstance(v, dict):
        raise Unsupported(f"material {name!r}: textured {key} (only constant colours convert)")
    return v


def bsdf(name, m):
    for key in ("ambient", "specular", "absorption"):
        v = m.get(key)
        if isinstance(v, dict) or nonzero(v):
            raise Unsupported(f"material {name!r}: {key} is Whitted's own (or needs a medium)")
    if m.get("roughness", 0) > 0:
        raise Unsupported(f"material {name!r}: roughness (GGX) is not converted yet")
    d = const_colour(m, "diffuse", name)
    r = m.get("reflectivity")
    t = m.get("transmissivity")
    lobes = [x for x in (nonzero(d), nonzero(r), nonzero(t)) if x]
    if len(lobes) > 1:
        raise Unsupported(f"material {name!r}: more than one lobe (diffuse, reflectivity, "
                          "transmissivity) has no exact Mitsuba equivalent")
    if nonzero(t):
        return {"type": "dielectric", "int_ior": float(m.get("ior", 1.5)), "ext_ior": 1.0,
                "specular_reflectance": rgb(t), "specular_transmittance": rgb(t)}
    if nonzero(r):
        return {"type": "twosided", "bsdf": {"type": "conductor", "material": "none",
                                             "specular_reflectance": rgb(r)}}
    return {"type": "twosided", "bsdf": {"type": "diffuse",
                                         "reflectance": rgb(d if d is not None else [0, 0, 0])}}


def frame_to_world(corner, eu, ev):
    """The affine map of Mitsuba's rectangle [-1,1]^2 x {0} onto corner + s eu + t ev."""
    import mitsuba as mi
    c = np.array(corner, float) + 0.5 * (np.array(eu, float) + np.array(ev, float))
    u = 0.5 * np.array(eu, float)
    v = 0.5 * np.array(ev, float)
    n = np.cross(u, v)
    n /= np.linalg.norm(n)
    m = np.identity(4)
    m[:3, 0], m[:3, 1], m[:3, 2], m[:3, 3] = u, v, n, c
    return mi.ScalarTransform4f(m.tolist())


def shape(o, mats, ids):
    import mitsuba as mi
    kind = o["type"]
    if kind == "sphere":
        s = {"type": "sphere", "center": o["center"], "radius": float(o["radius"])}
    elif kind == "quad":
        s = {"type": "rectangle", "to_world": frame_to_world(o["corner"], o["edge_u"], o["edge_v"])}
    elif kind == "plane":
        n = np.array(o["normal"], float)
        n /= np.linalg.norm(n)
        a = np.cross(n, [1.0, 0, 0] if abs(n[0]) < 0.9 else [0, 1.0, 0])
        a /= np.linalg.norm(a)
        b = np.cross(n, a)
        big = 1e4
        corner = np.array(o["point"], float) - big * (a + b)
        s = {"type": "rectangle", "to_world": frame_to_world(corner, 2 * big * b, 2 * big * a)}
    elif kind == "triangle":
        v = np.array(o["vertices"], float)
        path = os.path.join(ids["dir"], f"tri{len(ids['files'])}.obj")
        with open(path, "w") as f:
            for p in v:
                f.write(f"v {p[0]!r} {p[1]!r} {p[2]!r}\n")
            f.write("f 1 2 3\n")
        ids["files"].append(path)
        s = {"type": "obj", "filename": path, "face_normals": True}
    elif kind == "box":
        lo, hi = np.array(o["min"], float), np.array(o["max"], float)
        s = {"type": "cube", "to_world": mi.ScalarTransform4f().translate(((lo + hi) / 2).tolist())
             @ mi.ScalarTransform4f().scale(((hi - lo) / 2).tolist())}
    else:
        raise Unsupported(f"object type {kind!r}")
    m = mats[o["material"]]
    s["bsdf"] = bsdf(o["material"], m)
    if nonzero(m.get("emission")):
        s["emitter"] = {"type": "area", "radiance": rgb(m["emission"])}
    return s


def to_mitsuba(scene, size, spp, max_depth, workdir):
    """A Mitsuba 3 scene dict of a raytree scene (see the module doc for what converts)."""
    import mitsuba as mi
    cam = scene["camera"]
    if cam.get("aperture_radius", 0) > 0:
        raise Unsupported("thin lens camera")
    w, h = size or (cam["width"], cam["height"])
    d = {
        "type": "scene",
        "integrator": {"type": "path", "max_depth": max_depth + 2, "hide_emitters": False},
        "sensor": {
            "type": "perspective", "fov": float(cam["fov_y"]), "fov_axis": "y",
            "to_world": mi.ScalarTransform4f().look_at(
                origin=cam["position"], target=cam["look_at"], up=cam.get("up", [0, 1, 0])),
            "film": {"type": "hdrfilm", "width": w, "height": h, "pixel_format": "rgb",
                     "rfilter": {"type": "box"}},
            "sampler": {"type": "independent", "sample_count": spp},
        },
    }
    if nonzero(scene.get("ambient")):
        raise Unsupported("ambient light is Whitted's own")
    if nonzero(scene.get("background")):
        d["background"] = {"type": "constant", "radiance": rgb(scene["background"])}
    mats = scene.get("materials", {})
    ids = {"dir": workdir, "files": []}
    for i, o in enumerate(scene.get("objects", [])):
        d[f"obj{i}"] = shape(o, mats, ids)
    for i, l in enumerate(scene.get("lights", [])):
        if l["type"] == "point":
            d[f"light{i}"] = {"type": "point", "position": l["position"],
                              "intensity": rgb(l["intensity"])}
        elif l["type"] == "directional":
            d[f"light{i}"] = {"type": "directional", "direction": l["direction"],
                              "irradiance": rgb(l["irradiance"])}
        else:
            raise Unsupported(f"light type {l['type']!r}")
    return d


def rel_rmse(img, ref):
    return float(np.sqrt(np.mean(((img - ref) / (ref + 1e-2)) ** 2)))


def mitsuba_render(scene_dict, spp, seed=0):
    import mitsuba as mi
    import drjit as dr
    scene = mi.load_dict(scene_dict)
    t = time.perf_counter()
    img = mi.render(scene, spp=spp, seed=seed)
    dr.eval(img)
    arr = np.array(img)[:, :, :3]
    return arr, time.perf_counter() - t


def raytree_render(path, flags, size, max_depth, integrator, extra, out):
    """The image, raytree's own render time (the `time X s` it prints) and the wall time."""
    import mitsuba as mi
    cmd = [RAYTREE, "render", path, "--max-depth", str(max_depth),
           "--integrator", integrator, "-o", out] + flags + extra
    if size:
        cmd += ["--size", f"{size[0]}x{size[1]}"]
    t = time.perf_counter()
    run = subprocess.run(cmd, check=True, stdout=subprocess.PIPE, text=True)
    wall = time.perf_counter() - t
    m = re.search(r"^time ([0-9.]+) s", run.stdout, re.M)
    if not m:
        raise RuntimeError(f"no render time in raytree's output: {run.stdout!r}")
    return np.array(mi.Bitmap(out))[:, :, :3], float(m.group(1)), wall


def time_to_error(curve, target):
    """Seconds at which `curve` [(secs, err)] reaches `target`, log-log interpolated between
    its points; outside them extrapolated with Monte Carlo's err ~ secs^-1/2 from the nearest
    end (second value True then)."""
    pts = sorted(curve)
    for (t0, e0), (t1, e1) in zip(pts, pts[1:]):
        if min(e0, e1) <= target <= max(e0, e1):
            if e0 == e1:
                return t0, False
            f = (math.log(target) - math.log(e0)) / (math.log(e1) - math.log(e0))
            return math.exp(math.log(t0) + f * (math.log(t1) - math.log(t0))), False
    t, e = pts[0] if target > pts[0][1] else pts[-1]
    return t * (e / target) ** 2, True


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("scenes", nargs="+")
    ap.add_argument("--out", default="/tmp/raytree-mitsuba")
    ap.add_argument("--integrator", default="whitted")
    ap.add_argument("--size", default=None)
    ap.add_argument("--ref-spp", type=int, default=4096)
    ap.add_argument("--raytree-spp", default="1,2,4,8,16,32")
    ap.add_argument("--mitsuba-spp", default="4,16,64,256")
    ap.add_argument("--max-depth", type=int, default=32)
    ap.add_argument("--raytree", default="", help="extra raytree flags")
    ap.add_argument("--raytree-configs", default=None,
                    help="semicolon-separated raytree flag sets, one render each (replaces "
                         "--raytree-spp)")
    a = ap.parse_args()
    import mitsuba as mi
    mi.set_variant("llvm_ad_rgb")
    os.makedirs(a.out, exist_ok=True)
    size = tuple(int(x) for x in a.size.split("x")) if a.size else None
    print(f"# {os.uname().nodename}, {os.cpu_count()} cpus, mitsuba {mi.__version__} llvm_ad_rgb")
    for path in a.scenes:
        scene = json.load(open(path))
        name = os.path.splitext(os.path.basename(path))[0]
        try:
            d = to_mitsuba(scene, size, 1, a.max_depth, a.out)
        except Unsupported as e:
            print(f"{name}: skipped: {e}")
            continue
        key = hashlib.sha1(json.dumps([scene, a.size, a.max_depth]).encode()).hexdigest()[:10]
        ref_path = os.path.join(a.out, f"{name}-ref{a.ref_spp}-{key}.npy")
        if os.path.exists(ref_path):
            ref = np.load(ref_path)
        else:
            ref, secs = mitsuba_render(d, a.ref_spp, seed=12345)
            np.save(ref_path, ref)
            print(f"{name}: reference {a.ref_spp} spp in {secs:.1f} s")
        mitsuba_render(d, 1)  # compile (kernels are cached for the timed runs)
        # Interleaved (mitsuba, raytree, mitsuba, ...) so that load on the machine hits both.
        mts, rt, walls = [], [], []
        out = os.path.join(a.out, f"{name}-raytree.exr")
        jobs = [("mitsuba", int(s)) for s in a.mitsuba_spp.split(",")]
        if a.raytree_configs:
            jobs2 = [("raytree", c.strip()) for c in a.raytree_configs.split(";") if c.strip()]
        else:
            jobs2 = [("raytree", f"--spp {int(s)}") for s in a.raytree_spp.split(",")]
        order = [j for pair in zip(jobs, jobs2) for j in pair]
        order += jobs[len(jobs2):] + jobs2[len(jobs):]
        walls, labels = [], []
        for who, job in order:
            if who == "mitsuba":
                img, secs = mitsuba_render(d, job)
                mts.append((secs, rel_rmse(img, ref)))
                print(f"{name}: mitsuba  {job:5d} spp {secs:8.3f} s rel-RMSE {mts[-1][1]:.4f}",
                      flush=True)
            else:
                img, secs, wall = raytree_render(path, job.split(), size, a.max_depth,
                                                 a.integrator, a.raytree.split(), out)
                rt.append((secs, rel_rmse(img, ref)))
                walls.append(wall)
                labels.append(job)
                print(f"{name}: raytree  {job}: render {secs:8.3f} s, wall {wall:8.3f} s, "
                      f"rel-RMSE {rt[-1][1]:.4f} load {os.getloadavg()[0]:.1f}", flush=True)
        # For each raytree render: the time Mitsuba needs for the same error, and the ratio.
        print(f"{name}: raytree flags | rel-RMSE | raytree render s | wall s | "
              "mitsuba s (interpolated) | render / mitsuba | wall / mitsuba")
        for (secs, err), wall, label in zip(rt, walls, labels):
            tm, extrapolated = time_to_error(mts, err)
            cell = f"{tm:9.3f}{'~' if extrapolated else ' '} | {secs / tm:5.2f} | {wall / tm:5.2f}"
            print(f"{name}: {label} | {err:8.4f} | {secs:9.3f} | {wall:7.3f} | {cell}")

if __name__ == "__main__":
    sys.exit(main())
