"""Time to equal error: raytree against Mitsuba 3 (`llvm_ad_rgb`) on the same scene, one run.

For each scene the script converts the raytree JSON to a Mitsuba 3 scene (`to_mitsuba`), renders
references with Mitsuba (its `path`, and with `--ref-integrator path,ptracer` its `ptracer` too;
each in 16 independent passes, cached beside the output, their spread giving the reference's
own noise), then renders the scene with both renderers at increasing spp and reports the
relative RMSE against the reference and the time of each render. With `--agreement`, it first
compares raytree's mean per 8x8 block with the references' (below).

Integrators: raytree's `--integrator whitted,path,light,bdpt` (any of them, comma-separated)
against Mitsuba's `--mitsuba-integrator path,ptracer`, both with raytree's depth (Mitsuba's
`max_depth` is raytree's `--max-depth` + 2: Mitsuba counts segments, raytree scattering
vertices beyond the first) and their default roulette (`rr_depth` 5 both), emitters visible
(`hide_emitters` false). The equal-error table takes, at each raytree render's error, raytree's
fastest integrator to it against Mitsuba's fastest (and, when raytree's `path` ran, against
it).

Like with like under light tracing: neither raytree's `light` nor Mitsuba's `ptracer` sees a
mirror or glass from the camera (no connection reaches a pinhole through a delta lobe), so with
`--region diffuse` the error is measured only over the pixels whose camera rays (4 x 4 per
pixel, cast by Mitsuba) all miss or first hit a surface without a delta lobe, the same pixels for
every renderer and integrator. Emitters seen directly are counted by both (raytree's `light`
adds them with a camera ray, `ptracer` connects emitter samples to the camera; the caustic
fixture's lamp is out of frame). With `--error-ref path+ptracer` the reference on those pixels
is the two Mitsuba references combined by inverse variance (8x8-block smoothed; `path`'s
elsewhere). With `--subtract-ref-var` the reference's own per-pixel variance is taken off each
squared difference, so the errors are those against the exact image as far as the reference
can tell (the raw figure is printed beside it).

Per-block agreement (`--agreement SEEDSxSPP`, e.g. `8x64`): SEEDS raytree renders per integrator
(`--seed 1..SEEDS`), block means and their standard errors over the seeds, against each
reference's block means and standard errors over its passes: the fraction of blocks and
channels within 3 and 5 standard errors, the largest |z|, the largest relative block difference
(blocks brighter than 1% of the mean) and the relative difference of the image means. raytree's
`light` against Mitsuba's `path`, and everything else against `ptracer`, only over the blocks
that see no delta surface; and the two Mitsuba references against each other.

Timing, made fair: Mitsuba's time is `mi.render` up to the image in numpy (Dr.Jit launches
asynchronously), in passes of at most `--pass-spp` (256) spp so the LLVM wavefront fits in
memory, on a scene loaded beforehand (so scene loading, BVH build and writing are outside it).
`ptracer`'s kernels are compiled per spp: with `--repeat 2` every render runs twice and its
fastest time counts, which leaves the compilation out for both renderers and the uneven load of
a shared machine mostly out. raytree's time is the `time X s` `raytree render` prints, which
likewise starts after the scene is loaded and its BVH built and stops before the image is
encoded; its wall time (process start, JSON, BVH, render, EXR) is printed beside it. The
renders are interleaved, one of each renderer and integrator in turn, so that load hits all.
From the error-vs-seconds curves it interpolates (log-log) the time each needs to reach the
same error (`~`: extrapolated with err ~ t^-1/2).

Only light transport both renderers compute the same way can be compared: the scenes must use
constant colours, `diffuse` (Lambert), `reflectivity` (a mirror without Fresnel: Mitsuba's
`conductor` with `material: none`), `transmissivity` + `ior` (a smooth dielectric with exact
Fresnel: Mitsuba's `dielectric`), `emission` (an area emitter on the outer side), point and
directional lights, a constant background (an environment), spheres, planes (a large
rectangle), quads, triangles and boxes. Ambient, Blinn-Phong `specular`, textures, absorption
and translucent shadows are Whitted's own and refused with the reason (the caustic and Cornell
fixtures convert as they are). The Whitted integrator adds no light reflected diffusely, so for
`--integrator whitted` a scene must have no diffuse surface lit by anything but point and
directional lights with nothing reflective to see it (e.g. emitters seen through glass and
mirrors): the bench scenes in benches/mitsuba-scenes/ are built that way.

Not run by CI (it needs PyPI and Debian packages). Set-up, and the tables in docs/cost.md
(Whitted, path) and docs/bidirectional.md (light, bdpt):

    apt-get install -y libllvm19 && pip install mitsuba numpy
    export DRJIT_LIBLLVM_PATH=/usr/lib/x86_64-linux-gnu/libLLVM.so.19.1
    cargo build --release
    python3 benches/vs_mitsuba.py benches/mitsuba-scenes/glass-emitters.json --out /tmp/mts
    RAYTREE=target/release/raytree python3 benches/vs_mitsuba.py fixtures/caustic.json \
      --size 160x120 --max-depth 16 --integrator path,light,bdpt \
      --mitsuba-integrator path,ptracer --ref-integrator path,ptracer \
      --error-ref path+ptracer --region diffuse --subtract-ref-var --agreement 16x64 \
      --repeat 2 --min-spp 64 --targets 0.3,0.2,0.15,0.1,0.075,0.06 \
      --raytree-spp "path=4,16,64,256,1024;light=4,16,64,256,1024;bdpt=4,16,64,256" \
      --mitsuba-spp 4,16,64,256,1024,2048

Options: `--integrator` and `--mitsuba-integrator` (above), `--size WxH`, `--ref-spp N` (each
reference, default 4096), `--ref-integrator`, `--error-ref`, `--region all|diffuse`,
`--subtract-ref-var`, `--pass-spp N`, `--raytree-spp 1,4,16,...` and `--mitsuba-spp 4,16,...` (for
every integrator, or per integrator: `"path=4,16;bdpt=1,4"`), `--repeat R`, `--min-spp N`
and `--targets 0.3,0.2,...` (the equal-error table's curves and rows), `--agreement SxN`,
`--no-timing` (references and agreement only), `--max-depth D` (both; default 32),
`--raytree ARGS` (extra raytree flags), `--raytree-configs "A;B;..."` (instead of
`--raytree-spp`, with one `--integrator`: one raytree render per semicolon-separated set of
flags, e.g. `"--spp 4;--spp 2 --adaptive 0.1 --max-spp 16"`). It also writes
OUT/SCENE-results.json (every render's error and times).
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


def to_mitsuba(scene, size, spp, max_depth, workdir, integrator="path"):
    """A Mitsuba 3 scene dict of a raytree scene (see the module doc for what converts)."""
    import mitsuba as mi
    cam = scene["camera"]
    if cam.get("aperture_radius", 0) > 0:
        raise Unsupported("thin lens camera")
    w, h = size or (cam["width"], cam["height"])
    d = {
        "type": "scene",
        "integrator": mitsuba_integrator(integrator, max_depth),
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


def mitsuba_integrator(kind, max_depth):
    """Mitsuba's `path` or `ptracer` with raytree's depth: raytree's `max_depth` allows paths of
    up to `max_depth + 1` scattering vertices, Mitsuba's counts segments (1: emitters seen
    directly), hence `+ 2`. Emitters stay visible (`hide_emitters` false: `ptracer` then
    connects emitter samples to the camera, raytree's `light` adds them by a camera ray). Both
    keep their default roulette (`rr_depth` 5)."""
    if kind not in ("path", "ptracer"):
        raise ValueError(f"Mitsuba integrator {kind!r} (path or ptracer)")
    return {"type": kind, "max_depth": max_depth + 2, "hide_emitters": False}


def rel_rmse(img, ref, mask=None, ref_var=None):
    """sqrt(mean(((img - ref) / (ref + 0.01))^2)) over `mask`; with `ref_var` (the reference's
    per-pixel variance, estimated from its passes) that variance is taken off each squared
    difference first: the error against the exact image, as far as the reference can tell."""
    d = (img - ref) ** 2
    if ref_var is not None:
        d = d - ref_var
    e = d / (ref + 1e-2) ** 2
    if mask is not None:
        e = e[mask]
    return float(np.sqrt(max(np.mean(e), 1e-12)))


def smooth(v, b=8):
    """Each pixel's value replaced by its b x b block's mean (the image cropped to whole
    blocks and padded back by the edge blocks)."""
    m = np.repeat(np.repeat(blocks(v, b), b, axis=0), b, axis=1)
    return np.pad(m, [(0, v.shape[0] - m.shape[0]), (0, v.shape[1] - m.shape[1])] +
                  [(0, 0)] * (v.ndim - 2), mode="edge")


def mitsuba_render(mscene, spp, seed=0, pass_spp=256):
    """The image (mean of passes of at most `pass_spp`, each its own seed, so that the LLVM
    wavefront stays within memory) and the seconds of `mi.render` up to the image in numpy
    (Dr.Jit launches asynchronously; `np.array` waits for it)."""
    import mitsuba as mi
    acc, left, k, secs = 0.0, spp, 0, 0.0
    while left > 0:
        n = min(left, pass_spp)
        t = time.perf_counter()
        img = np.array(mi.render(mscene, spp=n, seed=seed * 7919 + k))[:, :, :3]
        secs += time.perf_counter() - t
        acc = acc + img * n
        left -= n
        k += 1
    return acc / spp, secs


def raytree_render(path, integrator, flags, size, max_depth, extra, out):
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


def diffuse_mask(mscene, n=4):
    """Pixels whose camera rays (n x n per pixel) all miss or first hit a surface without a
    delta lobe: what light tracing (raytree's `light`, Mitsuba's `ptracer`) can see."""
    import mitsuba as mi
    sensor = mscene.sensors()[0]
    w, h = sensor.film().crop_size()
    ys, xs = np.mgrid[0:h * n, 0:w * n]
    pos = mi.Point2f(((xs + 0.5) / (w * n)).ravel(), ((ys + 0.5) / (h * n)).ravel())
    ray, _ = sensor.sample_ray(0.0, 0.5, pos, mi.Point2f(0.5, 0.5))
    si = mscene.ray_intersect(ray)
    delta = mi.has_flag(si.bsdf(ray).flags(), mi.BSDFFlags.Delta) & si.is_valid()
    return ~np.array(delta).reshape(h, n, w, n).any(axis=(1, 3))


def blocks(img, b=8):
    """Means of the b x b blocks (the image cropped to whole blocks): (H/b, W/b, ...)."""
    h, w = img.shape[0] // b * b, img.shape[1] // b * b
    x = img[:h, :w]
    return x.reshape(h // b, b, w // b, b, *x.shape[2:]).mean(axis=(1, 3))


def block_stats(images):
    """Block means over a stack of independent images and their standard errors."""
    bs = np.stack([blocks(i) for i in images])
    return bs.mean(axis=0), bs.std(axis=0, ddof=1) / math.sqrt(len(bs))


def agreement(a, b, block_mask=None):
    """Per-block agreement of two (mean, standard error) block sets: the fraction of blocks
    and channels within 3 and 5 standard errors of the difference, the largest |z|, the
    largest relative block difference (blocks brighter than 1% of the mean) and the relative
    difference of the image means."""
    (ma, sa), (mb, sb) = a, b
    keep = np.ones(ma.shape[:2], bool) if block_mask is None else block_mask
    ma, sa, mb, sb = ma[keep], sa[keep], mb[keep], sb[keep]
    z = np.abs(ma - mb) / np.sqrt(sa ** 2 + sb ** 2 + 1e-30)
    lit = mb > 0.01 * mb.mean()
    rel = np.abs(ma - mb)[lit] / mb[lit]
    worst = np.argwhere(keep)[np.argsort(-z.max(axis=-1))[:3]]
    return {"blocks": int(keep.sum()), "within3": float(np.mean(z < 3)),
            "within5": float(np.mean(z < 5)), "max_z": float(z.max()),
            "max_rel": float(rel.max()) if rel.size else 0.0,
            "mean_rel": float(ma.mean() / mb.mean() - 1),
            "worst_blocks": [(int(x) * 8, int(y) * 8) for y, x in worst]}


def fmt_agreement(r):
    return (f"{r['blocks']} blocks x 3 channels: {r['within3']:.1%} within 3 SE, "
            f"{r['within5']:.1%} within 5, max |z| {r['max_z']:.2f}, max block difference "
            f"{r['max_rel']:.1%}, image mean {r['mean_rel']:+.2%}; worst blocks at (x, y) "
            f"{', '.join(f'{x},{y}' for x, y in r['worst_blocks'])}")


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


def best_time(curves, target):
    """The fastest of several curves to `target`: (kind, secs, extrapolated)."""
    return min(((k,) + time_to_error(c, target) for k, c in curves.items() if c),
               key=lambda x: x[1])


def spp_lists(arg, kinds):
    """`4,16,64` for every kind, or per kind `path=4,16;light=1,4` (kinds not named: none)."""
    if "=" not in arg:
        return {k: [int(s) for s in arg.split(",")] for k in kinds}
    out = {k: [] for k in kinds}
    for part in arg.split(";"):
        if part.strip():
            k, v = part.split("=")
            if k.strip() in out:
                out[k.strip()] = [int(s) for s in v.split(",")]
    return out


def fmt_t(t, extrapolated):
    return f"{t:.3f}{'~' if extrapolated else ''}"


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("scenes", nargs="+")
    ap.add_argument("--out", default="/tmp/raytree-mitsuba")
    ap.add_argument("--integrator", default="whitted",
                    help="raytree's, comma-separated: whitted,path,light,bdpt")
    ap.add_argument("--mitsuba-integrator", default="path",
                    help="Mitsuba's, comma-separated: path,ptracer")
    ap.add_argument("--size", default=None)
    ap.add_argument("--ref-spp", type=int, default=4096)
    ap.add_argument("--ref-integrator", default="path",
                    help="Mitsuba integrators to render references with (comma-separated); "
                         "the first is the one errors are measured against unless --error-ref")
    ap.add_argument("--error-ref", default=None,
                    help="path, ptracer or path+ptracer (both references, weighted by their "
                         "inverse variance, 8x8-block smoothed, where light tracing sees the "
                         "pixel; path's elsewhere)")
    ap.add_argument("--subtract-ref-var", action="store_true",
                    help="take the reference's own per-pixel variance off the squared errors")
    ap.add_argument("--region", default="all", choices=["all", "diffuse"],
                    help="pixels the error is measured over: all, or those whose camera rays "
                         "all see a surface without a delta lobe (what light tracing sees)")
    ap.add_argument("--pass-spp", type=int, default=256,
                    help="Mitsuba renders in passes of at most this many spp")
    ap.add_argument("--raytree-spp", default="1,2,4,8,16,32")
    ap.add_argument("--mitsuba-spp", default="4,16,64,256")
    ap.add_argument("--repeat", type=int, default=1,
                    help="run the timed schedule this many times; each render's time is its "
                         "fastest (the first run also compiles Mitsuba's kernels for each spp)")
    ap.add_argument("--agreement", default=None, metavar="SEEDSxSPP",
                    help="per-block agreement: SEEDS raytree renders of SPP each per "
                         "integrator against the references, e.g. 8x64")
    ap.add_argument("--no-timing", action="store_true", help="agreement only")
    ap.add_argument("--min-spp", type=int, default=1,
                    help="renders of fewer spp are listed but left out of the equal-error "
                         "curves (where a rare bright path, missed at low spp, makes the error "
                         "fall and rise again)")
    ap.add_argument("--targets", default=None,
                    help="comma-separated rel-RMSE levels of the equal-error table (default: "
                         "the errors of raytree's renders)")
    ap.add_argument("--max-depth", type=int, default=32)
    ap.add_argument("--raytree", default="", help="extra raytree flags")
    ap.add_argument("--raytree-configs", default=None,
                    help="semicolon-separated raytree flag sets, one render each (replaces "
                         "--raytree-spp; with a single --integrator)")
    a = ap.parse_args()
    import mitsuba as mi
    mi.set_variant("llvm_ad_rgb")
    os.makedirs(a.out, exist_ok=True)
    size = tuple(int(x) for x in a.size.split("x")) if a.size else None
    rt_kinds = [k.strip() for k in a.integrator.split(",") if k.strip()]
    mts_kinds = [k.strip() for k in a.mitsuba_integrator.split(",") if k.strip()]
    ref_kinds = [k.strip() for k in a.ref_integrator.split(",") if k.strip()]
    err_ref = a.error_ref or ref_kinds[0]
    for k in err_ref.split("+"):
        if k not in ref_kinds:
            ref_kinds.append(k)
    print(f"# {os.uname().nodename}, {os.cpu_count()} cpus, mitsuba {mi.__version__} "
          f"llvm_ad_rgb, {time.strftime('%Y-%m-%d %H:%M UTC', time.gmtime())}, load "
          f"{os.getloadavg()[0]:.1f}", flush=True)
    for path in a.scenes:
        scene = json.load(open(path))
        name = os.path.splitext(os.path.basename(path))[0]
        try:
            mscenes = {k: mi.load_dict(to_mitsuba(scene, size, 1, a.max_depth, a.out, k))
                       for k in sorted(set(mts_kinds + ref_kinds))}
        except Unsupported as e:
            print(f"{name}: skipped: {e}")
            continue
        mask = diffuse_mask(next(iter(mscenes.values())))
        region = mask if a.region == "diffuse" else None
        h, w = mask.shape
        bmask = blocks(mask.astype(float)) == 1.0
        print(f"{name}: {w}x{h}, max depth {a.max_depth}; {mask.mean():.1%} of the pixels "
              f"(and {bmask.mean():.1%} of the 8x8 blocks) see no delta surface first; error "
              f"over {'those' if region is not None else 'all pixels'} against Mitsuba "
              f"{err_ref}", flush=True)
        # References: independent passes (their spread gives the standard errors).
        refs = {}
        for k in ref_kinds:
            key = hashlib.sha1(json.dumps([scene, a.size, a.max_depth, k, a.ref_spp,
                                           a.pass_spp]).encode()).hexdigest()[:10]
            ref_path = os.path.join(a.out, f"{name}-ref-{k}{a.ref_spp}-{key}.npy")
            if os.path.exists(ref_path):
                stack = np.load(ref_path)
            else:
                t = time.perf_counter()
                n = max(a.ref_spp // a.pass_spp, 1)
                stack = np.stack([mitsuba_render(mscenes[k], a.ref_spp // n, seed=1000 + i,
                                                 pass_spp=a.pass_spp)[0] for i in range(n)])
                np.save(ref_path, stack)
                print(f"{name}: reference Mitsuba {k} {a.ref_spp} spp ({n} passes) in "
                      f"{time.perf_counter() - t:.1f} s", flush=True)
            mean = stack.mean(axis=0)
            noise = np.sqrt(stack.var(axis=0, ddof=1) / len(stack)) / (mean + 1e-2)
            floor = float(np.sqrt(np.mean((noise[region] if region is not None else noise) ** 2)))
            refs[k] = {"img": mean, "var": stack.var(axis=0, ddof=1) / len(stack),
                       "blocks": block_stats(list(stack)), "floor": floor}
            print(f"{name}: reference Mitsuba {k}: mean {mean.mean():.5f}, its own rel-RMSE "
                  f"(estimated from its passes) {floor:.4f}", flush=True)
        if err_ref == "path+ptracer":
            p, q = refs["path"], refs["ptracer"]
            vp, vq = smooth(p["var"]) + 1e-12, smooth(q["var"]) + 1e-12
            both = mask[:, :, None]
            img = np.where(both, (p["img"] / vp + q["img"] / vq) / (1 / vp + 1 / vq), p["img"])
            var = np.where(both, p["var"] * (vq / (vp + vq)) ** 2 + q["var"] * (vp / (vp + vq)) ** 2,
                           p["var"])
            noise = np.sqrt(var) / (img + 1e-2)
            floor = float(np.sqrt(np.mean((noise[region] if region is not None else noise) ** 2)))
            refs[err_ref] = {"img": img, "var": var, "floor": floor}
            print(f"{name}: reference path+ptracer: mean {img.mean():.5f}, its own rel-RMSE "
                  f"{floor:.4f}", flush=True)
        ref = refs[err_ref]["img"]
        ref_var = refs[err_ref]["var"] if a.subtract_ref_var else None
        if a.agreement:
            seeds, spp = (int(x) for x in a.agreement.split("x"))
            if "path" in refs and "ptracer" in refs:
                r = agreement(refs["ptracer"]["blocks"], refs["path"]["blocks"], bmask)
                print(f"{name}: agreement Mitsuba ptracer vs Mitsuba path (blocks seeing no "
                      f"delta surface): {fmt_agreement(r)}", flush=True)
            out = os.path.join(a.out, f"{name}-agree.exr")
            for k in rt_kinds:
                imgs, secs = [], 0.0
                for s in range(seeds):
                    img, t, _ = raytree_render(path, k, ["--spp", str(spp), "--seed", str(s + 1)],
                                               size, a.max_depth, a.raytree.split(), out)
                    imgs.append(img)
                    secs += t
                bs = block_stats(imgs)
                for rk, rv in refs.items():
                    if "blocks" not in rv:
                        continue
                    # Light tracing cannot see delta surfaces from the camera: against
                    # Mitsuba's path, only the blocks that see none.
                    only = bmask if (k == "light") != (rk == "ptracer") else None
                    r = agreement(bs, rv["blocks"], only)
                    what = "blocks seeing no delta surface" if only is not None else "all blocks"
                    print(f"{name}: agreement raytree {k} ({seeds} x {spp} spp, {secs:.1f} s) vs "
                          f"Mitsuba {rk} ({what}): {fmt_agreement(r)}", flush=True)
        if a.no_timing:
            continue
        # The timed schedule, interleaved (one render of each kind in turn, Mitsuba and
        # raytree alternating) so that load on the machine hits all of them alike.
        if a.raytree_configs:
            rt_jobs = {rt_kinds[0]: [c.strip() for c in a.raytree_configs.split(";") if c.strip()]}
        else:
            rt_jobs = {k: [f"--spp {s}" for s in v]
                       for k, v in spp_lists(a.raytree_spp, rt_kinds).items()}
        mts_jobs = spp_lists(a.mitsuba_spp, mts_kinds)
        queues = [[("mitsuba", k, j) for j in mts_jobs[k]] for k in mts_kinds]
        queues += [[("raytree", k, j) for j in rt_jobs[k]] for k in rt_kinds]
        order = []
        for i in range(max(len(q) for q in queues)):
            order += [q[i] for q in queues if i < len(q)]
        results = {}  # (who, kind, job) -> [err, [secs...], wall]
        out = os.path.join(a.out, f"{name}-raytree.exr")
        for rep in range(a.repeat):
            for who, kind, job in order:
                load = os.getloadavg()[0]
                if who == "mitsuba":
                    img, secs = mitsuba_render(mscenes[kind], job, pass_spp=a.pass_spp)
                    wall = secs
                else:
                    img, secs, wall = raytree_render(path, kind, job.split(), size, a.max_depth,
                                                     a.raytree.split(), out)
                err = rel_rmse(img, ref, region, ref_var)
                raw = rel_rmse(img, ref, region)
                r = results.setdefault((who, kind, job), [err, [], wall])
                r[1].append(secs)
                print(f"{name}: [{rep + 1}] {who} {kind} {job}: {secs:8.3f} s (wall {wall:.3f}) "
                      f"rel-RMSE {err:.4f} (raw {raw:.4f}) load {load:.1f}", flush=True)
        curves = {}
        for (who, kind, job), (err, secs, wall) in results.items():
            m = re.search(r"(?:^| )--spp (\d+)", job) if who == "raytree" else None
            spp = job if who == "mitsuba" else int(m.group(1)) if m else a.min_spp
            if spp >= a.min_spp:
                curves.setdefault((who, kind), []).append((min(secs), err))
        mts_curves = {k: c for (who, k), c in curves.items() if who == "mitsuba"}
        rt_curves = {k: c for (who, k), c in curves.items() if who == "raytree"}
        print(f"\n{name}: every render (time: the fastest of {a.repeat}; rel-RMSE against the "
              f"Mitsuba {err_ref} reference, whose own is {refs[err_ref]['floor']:.4f}"
              f"{', taken off' if a.subtract_ref_var else ''})\n")
        print("| renderer | integrator | spp | rel-RMSE | s | " +
              " | ".join(f"Mitsuba {k} s for that error" for k in mts_kinds) +
              " | / Mitsuba's best |")
        print("|---|---|---|---:|---:|" + "---:|" * len(mts_kinds) + "---:|")
        for (who, kind, job), (err, secs, wall) in results.items():
            t = min(secs)
            cells = [time_to_error(mts_curves[k], err) if k in mts_curves else (math.inf, False)
                     for k in mts_kinds]
            best = min(c[0] for c in cells)
            spp = job if who == "mitsuba" else re.sub(r"^--spp (\d+)$", r"\1", job)
            print(f"| {who} | {kind} | {spp} | {err:.4f} | {t:.3f} | " +
                  " | ".join(fmt_t(*c) for c in cells) + f" | {t / best:.2f} |")
        # Equal error: at each raytree render's error, raytree's best integrator against
        # Mitsuba's best (and against raytree's own path when it ran).
        targets = [float(x) for x in a.targets.split(",")] if a.targets else sorted(
            {err for (who, k, j), (err, s, w) in results.items() if who == "raytree"},
            reverse=True)
        print(f"\n{name}: time to equal error, seconds (~: extrapolated with err ~ t^-1/2; "
              f"curves from {a.min_spp} spp)\n")
        rk_ = [k for k in rt_kinds if k in rt_curves]
        mk_ = [k for k in mts_kinds if k in mts_curves]
        others = [k for k in rk_ if k != "path"] if "path" in rt_curves else []
        extra = "".join(f" {k} / path |" for k in others)
        extra += " best / raytree path |" if "path" in rt_curves else ""
        print("| rel-RMSE | " + " | ".join(f"raytree {k}" for k in rk_) + " | " +
              " | ".join(f"Mitsuba {k}" for k in mk_) +
              " | raytree best / Mitsuba best |" + extra)
        print("|---:|" + "---:|" * (len(rk_) + len(mk_) + 1) + "---:|" * extra.count("|"))
        for e in targets:
            cells = [fmt_t(*time_to_error(rt_curves[k], e)) for k in rk_]
            cells += [fmt_t(*time_to_error(mts_curves[k], e)) for k in mk_]
            rk, rt, _ = best_time(rt_curves, e)
            mk, mt, _ = best_time(mts_curves, e)
            row = f"| {e:.4f} | " + " | ".join(cells) + f" | {rk} / {mk}: **{rt / mt:.2f}** |"
            if "path" in rt_curves:
                pt = time_to_error(rt_curves["path"], e)[0]
                for k in others:
                    row += f" {time_to_error(rt_curves[k], e)[0] / pt:.2f} |"
                row += f" {rt / pt:.2f} |"
            print(row)
        with open(os.path.join(a.out, f"{name}-results.json"), "w") as f:
            json.dump({"scene": path, "size": [w, h], "error_ref": err_ref,
                       "region": a.region, "renders": [
                           {"renderer": who, "integrator": k, "job": j, "err": e, "secs": s}
                           for (who, k, j), (e, s, _) in results.items()]}, f, indent=1)
        print(flush=True)


if __name__ == "__main__":
    sys.exit(main())
