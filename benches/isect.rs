//! The scene's ray queries (issues 15 and 18: intersection in small and medium scenes) beside
//! their baseline measured in the same run: a plain linear scan of `Shape::intersect` in
//! object order, which is what `Scene::intersect_counted` and `Scene::occluded` return and
//! what they cost before the objects were prepared and culled by their bounds (scenes of up
//! to 8 objects were scanned exactly so; glass-emitters' 9 took the object BVH, which its
//! profile showed no faster).
//!
//! Rays per scene: one camera ray per pixel; from each camera hit a bounce ray in a random
//! direction of the normal's hemisphere (closest hit) and a shadow ray to a random point of
//! the scene's bounds (any-hit, up to that point). One thread; the two are alternated and each
//! keeps its fastest of the passes, so load from other processes, which only adds time, hits
//! both alike. Both must give the same answers (checked).
//!
//! Run: `cargo bench --bench isect` (`-- --passes N`, default 9; `-- --only caustic` for one
//! scene). Figures: docs/cost.md.

use glam::DVec3;
use raytree::Scene;
use raytree::bvh::TraversalCost;
use raytree::math::Ray;
use std::hint::black_box;
use std::time::Instant;

const SCENES: [&str; 4] = [
    "benches/mitsuba-scenes/glass-emitters.json",
    "fixtures/cornell-box.json",
    "fixtures/caustic.json",
    "fixtures/classic.json",
];

struct Rays {
    closest: Vec<Ray>,
    shadow: Vec<(Ray, f64)>,
}

fn rays(s: &Scene) -> Rays {
    let film = s.camera.film();
    let mut seed = 1u64;
    let mut f = move || {
        seed ^= seed << 13;
        seed ^= seed >> 7;
        seed ^= seed << 17;
        (seed >> 11) as f64 / (1u64 << 53) as f64
    };
    let (mut lo, mut hi) = (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY));
    for o in &s.objects {
        if let Some((a, b)) = o.shape.bounds() {
            (lo, hi) = (lo.min(a), hi.max(b));
        }
    }
    let (mut closest, mut shadow) = (Vec::new(), Vec::new());
    for y in 0..s.camera.height {
        for x in 0..s.camera.width {
            let ray = film.ray(f64::from(x) + 0.5, f64::from(y) + 0.5);
            closest.push(ray);
            let Some(hit) = s.intersect(&ray, f64::INFINITY) else {
                continue;
            };
            let n = if hit.normal.dot(ray.direction) < 0.0 {
                hit.normal
            } else {
                -hit.normal
            };
            let p = ray.at(hit.t) + 1e-6 * n;
            let mut d = DVec3::new(2.0 * f() - 1.0, 2.0 * f() - 1.0, 2.0 * f() - 1.0);
            if d.dot(n) < 0.0 {
                d = -d;
            }
            closest.push(Ray::new(p, d.normalize_or(n), 1e-9));
            let target = lo + (hi - lo) * DVec3::new(f(), f(), f());
            let to = target - p;
            shadow.push((Ray::new(p, to.normalize_or(n), 1e-9), to.length()));
        }
    }
    Rays { closest, shadow }
}

/// The baseline: every object's `Shape::intersect` in object order (with the normal, as the
/// closest-hit query returns it).
fn linear_closest(s: &Scene, ray: &Ray) -> Option<(f64, usize, DVec3)> {
    let (mut best, mut t_max) = (None, f64::INFINITY);
    for (i, o) in s.objects.iter().enumerate() {
        if let Some(h) = o.shape.intersect(ray, t_max) {
            t_max = h.t;
            best = Some((h.t, i, h.normal));
        }
    }
    best
}

fn linear_any(s: &Scene, ray: &Ray, t_max: f64) -> bool {
    s.objects
        .iter()
        .any(|o| o.shape.intersect(ray, t_max).is_some())
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let passes: u32 = args
        .iter()
        .position(|a| a == "--passes")
        .and_then(|i| args.get(i + 1)?.parse().ok())
        .unwrap_or(9);
    // `--only NAME`: the scenes whose path contains NAME (for profiling).
    let only = args
        .iter()
        .position(|a| a == "--only")
        .and_then(|i| args.get(i + 1).cloned());
    eprintln!("one thread, fastest of {passes} alternated passes; Mrays/s (closest + any-hit)");
    for path in SCENES {
        if only.as_ref().is_some_and(|o| !path.contains(o.as_str())) {
            continue;
        }
        let src = std::fs::read_to_string(path).expect("scene file");
        let s = Scene::from_json(&src).expect("valid scene");
        let r = rays(&s);
        for ray in &r.closest {
            let a = s
                .intersect(ray, f64::INFINITY)
                .map(|h| (h.t, h.object, h.normal));
            assert_eq!(a, linear_closest(&s, ray), "{path}: {ray:?}");
        }
        for (ray, t) in &r.shadow {
            let mut cost = TraversalCost::default();
            assert_eq!(s.occluded(ray, *t, &mut cost), linear_any(&s, ray, *t));
        }
        let (mut new, mut old) = (f64::INFINITY, f64::INFINITY);
        for _ in 0..passes {
            let t = Instant::now();
            let mut cost = TraversalCost::default();
            for ray in &r.closest {
                black_box(black_box(&s).intersect_counted(ray, f64::INFINITY, &mut cost));
            }
            for (ray, d) in &r.shadow {
                black_box(black_box(&s).occluded(ray, *d, &mut cost));
            }
            new = new.min(t.elapsed().as_secs_f64());
            let t = Instant::now();
            for ray in &r.closest {
                black_box(linear_closest(black_box(&s), ray));
            }
            for (ray, d) in &r.shadow {
                black_box(linear_any(black_box(&s), ray, *d));
            }
            old = old.min(t.elapsed().as_secs_f64());
        }
        let n = (r.closest.len() + r.shadow.len()) as f64;
        eprintln!(
            "{path:<44} {} objects, {:>6} rays: queries {:6.2}, linear scan {:6.2} Mrays/s, \
             speed-up {:.2}x",
            s.objects.len(),
            n,
            n / new / 1e6,
            n / old / 1e6,
            old / new
        );
    }
}
