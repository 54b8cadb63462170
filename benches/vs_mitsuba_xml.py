"""raytree's path tracer against Mitsuba 3 on Mitsuba's own XML scenes, 8x8-block agreement.

Issue 29 ("Tests and figures"): render public Mitsuba 3 test scenes, as Mitsuba ships them,
with `raytree render SCENE.xml --integrator path` and with Mitsuba 3's `path` integrator at
matched settings, and compare the 8x8-pixel block means. The table in docs/scenes.md
("Checked against Mitsuba 3") was made with this script.

The corpus is not in this repository; fetch it anywhere and pass the scene files:

    git clone --depth 1 https://github.com/mitsuba-renderer/mitsuba-data /tmp/mitsuba-data
    apt-get install -y libllvm19 && pip install mitsuba numpy
    export DRJIT_LIBLLVM_PATH=/usr/lib/x86_64-linux-gnu/libLLVM.so.19.1
    python3 benches/vs_mitsuba_xml.py --bench-copies /tmp/mitsuba-data
    RAYTREE=target/release/raytree python3 benches/vs_mitsuba_xml.py \
        /tmp/mitsuba-data/scenes/cbox/cbox.xml \
        /tmp/mitsuba-data/scenes/cbox/cbox-rgb.bench.xml \
        /tmp/mitsuba-data/docs/scenes/integrator_direct_both.bench.xml --out /tmp/vs-xml

(docs/scenes.md has the exact runs: Veach at `--width 192`, the file's 3:2.)

Bench copies (`--bench-copies CORPUS` writes them beside the originals, in the corpus; both
renderers then read the same copy), because raytree refuses the originals (docs/scenes.md,
"Checked against Mitsuba 3"):

- `scenes/cbox/cbox-rgb.bench.xml`: `cbox-rgb.xml` with `fragments/shapes.xml` inlined and the
  top-level `<emitter type="area" id="area-emitter">` moved into the luminaire's `<shape>` in
  place of its `<ref id="area-emitter"/>` (raytree: "an area emitter must be inside a
  <shape>"; inlining also avoids the include-relative mesh lookup below);
- `docs/scenes/integrator_direct_both.bench.xml`: `integrator_direct_both.xml` with
  `<path value="."/>` added, so that the meshes `include/veach_mis.xml` names relative to the
  main scene's directory are found (raytree looks beside the including file and in `<path>`
  directories, not in the main scene's directory, which Mitsuba searches).

Matched settings, per scene:

- raytree first converts the scene (`raytree convert`, with the same `-D`), and the script reads
  what raytree read from the converted JSON: `settings.max_depth`, the image size and the
  camera's vertical field of view (`camera.fov_y`). Mitsuba renders the scene as loaded
  (`mi.load_file(scene, **defines)`), but with a sensor rebuilt from the file's own (same
  `to_world`, near and far clip) with `fov_axis` y and raytree's `fov_y` (the script prints
  Mitsuba's own vertical field of view beside it: a loader check), an `hdrfilm` of the chosen
  size, a box filter and the `independent` sampler, and with the `path` integrator at
  `max_depth` = raytree's + 2 (docs/scenes.md, "Depth, samples and filters": Mitsuba counts
  path segments, raytree bounces after the first hit), `rr_depth` 5 (both renderers' default),
  emitters visible. Whatever integrator the file names is replaced by `path` in Mitsuba, and
  raytree renders with `--integrator path`.
- Size: `--width W` (default 128) with the file's aspect ratio (the height rounded), or
  `--size WxH`; both renderers get it (`--size` for raytree). `--max-depth D` overrides the
  depth for both (raytree's D, Mitsuba's D + 2).
- raytree: `--seeds K` renders (`--seed 1..K`) of `--spp N` each, `--filter box`,
  `--antialiasing uniform`. Mitsuba: `--ref-spp` in passes of `--pass-spp` samples, each pass
  its own seed (the reference is cached beside the output, keyed by the settings).

Comparison: luminance (Rec. 709 weights) of the 8x8 block means (the image cropped to whole
blocks); r = raytree's mean over its seeds, m = Mitsuba's over its passes; per block the
relative error |r - m| / m over the blocks with m above 1% of the mean block (skipped blocks are
counted); mean, median, 95th percentile and max of it; the image mean ratio (luminance and per
channel). Noise, so bias can be told from it: the standard errors of each block mean from the
spread over seeds (raytree) and passes (Mitsuba), their median relative to m, the mean relative
error expected from noise alone (sqrt(2/pi) sqrt(se_r^2 + se_m^2) / m, averaged), and
z = (r - m) / sqrt(se_r^2 + se_m^2): the fraction of blocks within |z| < 3 and the largest |z|.
The notes raytree prints on stderr when it loads the scene are saved to OUT/NAME.notes.txt
and printed.

Not run by CI (it needs the corpus, PyPI and Debian packages).
"""

import argparse
import hashlib
import json
import os
import re
import subprocess
import sys
import time

import numpy as np

RAYTREE = os.environ.get("RAYTREE", "target/release/raytree")
LUM = np.array([0.2126, 0.7152, 0.0722])


def run(cmd):
    t = time.time()
    p = subprocess.run(cmd, capture_output=True, text=True)
    return p, time.time() - t


def blocks(img, b=8):
    h, w = img.shape[0] // b * b, img.shape[1] // b * b
    x = img[:h, :w]
    return x.reshape(h // b, b, w // b, b, -1).mean(axis=(1, 3))


def name_of(path, used):
    base = os.path.splitext(os.path.basename(path))[0]
    n, i = base, 2
    while n in used:
        n, i = f"{base}-{i}", i + 1
    used.add(n)
    return n


def raytree_settings(scene, defines, out, name):
    js = os.path.join(out, f"{name}.raytree.json")
    cmd = [RAYTREE, "convert", scene, "-o", js]
    for d in defines:
        cmd += ["-D", d]
    p, _ = run(cmd)
    if p.returncode != 0:
        return None, p.stderr.strip()
    d = json.load(open(js))
    return d, p.stderr.strip()


def mitsuba_reference(mi, scene, defines, size, fov_y, max_depth, ref_spp, pass_spp, out, name):
    w, h = size
    key = json.dumps([os.path.abspath(scene), sorted(defines), size, fov_y, max_depth,
                      ref_spp, pass_spp, mi.variant()])
    cache = os.path.join(out, f"{name}-ref-{hashlib.sha1(key.encode()).hexdigest()[:10]}.npz")
    params = dict(d.split("=", 1) for d in defines)
    sc = mi.load_file(scene, **params)
    sen = sc.sensors()[0]
    kind = str(sen).split("[")[0]
    tp = mi.traverse(sen)
    m4 = np.array(sen.world_transform().matrix, dtype=np.float64)
    m4 = m4.reshape(4, 4) if m4.size == 16 else m4[..., 0]
    to_world = mi.ScalarTransform4f(m4.tolist())
    # Mitsuba's own vertical field of view of the file's sensor, for the record
    fw, fh = sen.film().size()
    x_fov = float(np.array(tp["x_fov"]).ravel()[0])
    own_fov_y = float(np.degrees(2 * np.arctan(np.tan(np.radians(x_fov) / 2) * fh / fw)))
    if os.path.exists(cache):
        z = np.load(cache)
        return z["passes"], float(z["secs"]), own_fov_y, (fw, fh), kind
    if "ThinLens" in kind:
        raise SystemExit(f"{scene}: thin-lens sensors are not rebuilt by this script")
    sensor = mi.load_dict({
        "type": "perspective",
        "fov_axis": "y",
        "fov": fov_y,
        "near_clip": float(np.array(tp["near_clip"]).ravel()[0]),
        "far_clip": float(np.array(tp["far_clip"]).ravel()[0]),
        "to_world": to_world,
        "sampler": {"type": "independent", "sample_count": pass_spp},
        "film": {"type": "hdrfilm", "width": w, "height": h, "rfilter": {"type": "box"},
                 "pixel_format": "rgb"},
    })
    integ = mi.load_dict({"type": "path", "max_depth": max_depth + 2, "rr_depth": 5,
                          "hide_emitters": False})
    passes = []
    t0 = time.time()
    for i in range((ref_spp + pass_spp - 1) // pass_spp):
        img = mi.render(sc, sensor=sensor, integrator=integ, spp=pass_spp, seed=1000 + i)
        passes.append(np.array(img, dtype=np.float64)[:, :, :3])
    secs = time.time() - t0
    passes = np.stack(passes)
    np.savez_compressed(cache, passes=passes, secs=secs)
    return passes, secs, own_fov_y, (fw, fh), kind


def stats(rt_imgs, ref_passes, b=8):
    """Block statistics of raytree's seeds against Mitsuba's passes (luminance)."""
    rb = np.stack([blocks(x, b) for x in rt_imgs])      # K x by x bx x 3
    mb = np.stack([blocks(x, b) for x in ref_passes])   # P x by x bx x 3
    rl, ml = rb @ LUM, mb @ LUM
    r, m = rl.mean(0), ml.mean(0)
    se_r = rl.std(0, ddof=1) / np.sqrt(len(rl))
    se_m = ml.std(0, ddof=1) / np.sqrt(len(ml))
    keep = m > 0.01 * m.mean()
    rel = np.abs(r - m)[keep] / m[keep]
    se = np.sqrt(se_r ** 2 + se_m ** 2)[keep]
    # blocks without noise (inside an emitter: both exact) would give |z| of float rounding
    z = (r - m)[keep] / np.maximum(se, 1e-5 * m[keep])
    rimg, mimg = np.mean(rt_imgs, 0), np.mean(ref_passes, 0)
    seed_means = np.array([x.reshape(-1, 3).mean(0) @ LUM for x in rt_imgs])
    pass_means = np.array([x.reshape(-1, 3).mean(0) @ LUM for x in ref_passes])
    return {
        "blocks": int(keep.sum()), "skipped": int((~keep).sum()),
        "rel_mean": float(rel.mean()), "rel_median": float(np.median(rel)),
        "rel_p95": float(np.percentile(rel, 95)), "rel_max": float(rel.max()),
        "worst_block": [int(v) for v in np.argwhere(keep)[np.argmax(rel)]],
        "mean_ratio": float((rimg.reshape(-1, 3).mean(0) @ LUM) /
                            (mimg.reshape(-1, 3).mean(0) @ LUM)),
        "mean_ratio_rgb": [float(v) for v in rimg.reshape(-1, 3).mean(0) /
                           np.maximum(mimg.reshape(-1, 3).mean(0), 1e-30)],
        # standard error of the ratio, from raytree's seeds and Mitsuba's passes
        "mean_ratio_se": float(np.hypot(
            seed_means.std(ddof=1) / np.sqrt(len(seed_means)) / seed_means.mean(),
            pass_means.std(ddof=1) / np.sqrt(len(pass_means)) / pass_means.mean())),
        "noise_rt_median": float(np.median(se_r[keep] / m[keep])),
        "noise_ref_median": float(np.median(se_m[keep] / m[keep])),
        "rel_expected_from_noise": float(np.mean(np.sqrt(2 / np.pi) * se / m[keep])),
        "z_within_3": float(np.mean(np.abs(z) < 3)), "z_max": float(np.abs(z).max()),
    }


def bench_copies(corpus):
    cb = os.path.join(corpus, "scenes", "cbox")
    root = open(os.path.join(cb, "cbox-rgb.xml")).read()
    shapes = open(os.path.join(cb, "fragments", "shapes.xml")).read()
    em = re.search(r'\s*<emitter type="area" id="area-emitter">.*?</emitter>', root, re.S).group(0)
    inner = re.search(r"<scene[^>]*>(.*)</scene>", shapes, re.S).group(1).strip()
    inner = inner.replace('<ref id="area-emitter"/>', em.replace(' id="area-emitter"', "").strip())
    out = root.replace(em, "").replace('<include filename="fragments/shapes.xml"/>', inner)
    open(os.path.join(cb, "cbox-rgb.bench.xml"), "w").write(out)
    ds = os.path.join(corpus, "docs", "scenes")
    src = open(os.path.join(ds, "integrator_direct_both.xml")).read()
    out = re.sub(r"(<scene [^>]*>)", r'\1\n    <path value="."/>', src, count=1)
    open(os.path.join(ds, "integrator_direct_both.bench.xml"), "w").write(out)
    print(f"wrote {cb}/cbox-rgb.bench.xml and {ds}/integrator_direct_both.bench.xml")


def main():
    if len(sys.argv) == 3 and sys.argv[1] == "--bench-copies":
        return bench_copies(sys.argv[2])
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("scenes", nargs="+", help="Mitsuba 3 XML scene files")
    ap.add_argument("--out", default="/tmp/vs-mitsuba-xml")
    ap.add_argument("--width", type=int, default=128)
    ap.add_argument("--size", help="WxH (overrides --width)")
    ap.add_argument("--spp", type=int, default=256, help="raytree spp per seed")
    ap.add_argument("--seeds", type=int, default=4)
    ap.add_argument("--ref-spp", type=int, default=4096)
    ap.add_argument("--pass-spp", type=int, default=256)
    ap.add_argument("--max-depth", type=int, help="override both (raytree's counting)")
    ap.add_argument("-D", dest="defines", action="append", default=[],
                    help="NAME=VALUE for $NAME, given to both renderers; repeatable")
    ap.add_argument("--variant", default="llvm_ad_rgb")
    ap.add_argument("--json", help="also write the results here")
    ap.add_argument("--ref-only", action="store_true", help="only render (cache) the references")
    ap.add_argument("--threads", type=int, help="Dr.Jit's thread count (default: all cores)")
    a = ap.parse_args()
    os.makedirs(a.out, exist_ok=True)

    import mitsuba as mi
    mi.set_variant(a.variant)
    if a.threads:
        import drjit as dr
        dr.set_thread_count(a.threads)

    used, results = set(), []
    for scene in a.scenes:
        name = name_of(scene, used)
        print(f"== {scene}")
        conv, notes = raytree_settings(scene, a.defines, a.out, name)
        if conv is None:
            print(f"raytree refuses it:\n{notes}")
            results.append({"scene": scene, "error": notes})
            continue
        cam, st = conv["camera"], conv["settings"]
        if a.size:
            size = tuple(int(v) for v in a.size.lower().split("x"))
        else:
            size = (a.width, max(8, round(a.width * cam["height"] / cam["width"])))
        depth = a.max_depth if a.max_depth is not None else st["max_depth"]
        print(f"raytree reads: {cam['width']}x{cam['height']}, fov_y {cam['fov_y']:.4f}, "
              f"max_depth {st['max_depth']}, spp {st['spp']}, filter {st.get('filter', 'box')}")
        print(f"rendering {size[0]}x{size[1]}, raytree max_depth {depth} "
              f"(Mitsuba {depth + 2})")

        passes, msecs, own_fov_y, own_size, kind = mitsuba_reference(
            mi, scene, a.defines, size, cam["fov_y"], depth, a.ref_spp, a.pass_spp,
            a.out, name)
        print(f"Mitsuba ({kind}, film {own_size[0]}x{own_size[1]}): own fov_y {own_fov_y:.4f}; "
              f"reference {len(passes)}x{a.pass_spp} spp, {msecs:.0f} s")
        if a.ref_only:
            continue

        rt_imgs, rt_secs, rt_notes = [], [], None
        for s in range(1, a.seeds + 1):
            tag = ("-" + hashlib.sha1(" ".join(a.defines).encode()).hexdigest()[:8]
                   if a.defines else "")
            exr = os.path.join(a.out,
                               f"{name}-rt-{size[0]}x{size[1]}-d{depth}-{a.spp}{tag}-s{s}.exr")
            cmd = [RAYTREE, "render", scene, "--integrator", "path", "--spp", str(a.spp),
                   "--size", f"{size[0]}x{size[1]}", "--max-depth", str(depth),
                   "--filter", "box", "--antialiasing", "uniform", "--seed", str(s),
                   "-o", exr]
            for d in a.defines:
                cmd += ["-D", d]
            if os.path.exists(exr) and os.path.exists(exr + ".stderr"):
                # rendered before with these settings (e.g. against another variant)
                err, secs = open(exr + ".stderr").read(), 0.0
            else:
                p, secs = run(cmd)
                if p.returncode != 0:
                    raise SystemExit(f"raytree render failed ({p.returncode}):\n{p.stderr}")
                err = p.stderr
                open(exr + ".stderr", "w").write(err)
            rt_notes = err.strip() if rt_notes is None else rt_notes
            rt_secs.append(secs)
            rt_imgs.append(np.array(mi.Bitmap(exr), dtype=np.float64)[:, :, :3])
        with open(os.path.join(a.out, f"{name}.notes.txt"), "w") as f:
            f.write(rt_notes + "\n")
        print(f"raytree: {a.seeds} x {a.spp} spp, {sum(rt_secs):.0f} s wall; stderr:")
        print("\n".join("  " + l for l in rt_notes.splitlines()))
        r = stats(rt_imgs, passes)
        r.update({"scene": scene, "size": list(size), "raytree_max_depth": depth,
                  "mitsuba_max_depth": depth + 2, "raytree_spp": [a.seeds, a.spp],
                  "ref_spp": [len(passes), a.pass_spp], "raytree_secs": sum(rt_secs),
                  "mitsuba_secs": msecs, "fov_y": [cam["fov_y"], own_fov_y],
                  "notes": rt_notes})
        results.append(r)
        print(json.dumps({k: v for k, v in r.items() if k != "notes"}, indent=1))

    print("\n| scene | blocks (skipped) | rel. error mean | median | p95 | max | image mean "
          "ratio (Y) | R, G, B | raytree noise | Mitsuba noise | expected from noise | "
          "abs z < 3 | max abs z |")
    print("| --- " * 13 + "|")
    for r in results:
        if "error" in r:
            print(f"| {r['scene']} | refused: {r['error'].splitlines()[0]} |")
            continue
        print(f"| {os.path.basename(r['scene'])} | {r['blocks']} ({r['skipped']}) | "
              f"{r['rel_mean']:.4f} | {r['rel_median']:.4f} | {r['rel_p95']:.4f} | "
              f"{r['rel_max']:.4f} | {r['mean_ratio']:.4f} +- {r['mean_ratio_se']:.4f} | "
              + ", ".join(f"{v:.4f}" for v in r["mean_ratio_rgb"]) +
              f" | {r['noise_rt_median']:.4f} | {r['noise_ref_median']:.4f} | "
              f"{r['rel_expected_from_noise']:.4f} | {r['z_within_3']:.3f} | "
              f"{r['z_max']:.1f} |")
    if a.json:
        json.dump(results, open(a.json, "w"), indent=1)


if __name__ == "__main__":
    main()
