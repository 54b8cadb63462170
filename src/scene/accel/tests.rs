//! The accelerated queries against a linear scan of [`Shape::intersect`] in object order, on
//! random scenes of spheres, quads, boxes, triangles and planes (small ones scanned through
//! their bounds, large ones through the BVH), with duplicated objects and shared faces for
//! ties, and rays from anywhere, along the axes and through corners and edges.

use super::*;
use glam::DVec3;

/// SplitMix64: a fixed, seedable sequence.
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^ (z >> 31)
    }
    fn f(&mut self) -> f64 {
        (self.next() >> 11) as f64 / (1u64 << 53) as f64
    }
    fn range(&mut self, a: f64, b: f64) -> f64 {
        a + (b - a) * self.f()
    }
    fn below(&mut self, n: usize) -> usize {
        (self.next() % n as u64) as usize
    }
    /// A point, on a coarse grid half the time (shared faces and edges).
    fn point(&mut self) -> DVec3 {
        let p = DVec3::new(
            self.range(-3.0, 3.0),
            self.range(-3.0, 3.0),
            self.range(-3.0, 3.0),
        );
        if self.f() < 0.5 {
            (p * 2.0).round() / 2.0
        } else {
            p
        }
    }
    fn dir(&mut self) -> DVec3 {
        loop {
            let d = DVec3::new(
                self.range(-1.0, 1.0),
                self.range(-1.0, 1.0),
                self.range(-1.0, 1.0),
            );
            if d.length_squared() > 1e-4 {
                return d;
            }
        }
    }
}

fn shape(r: &mut Rng) -> Shape {
    let p = r.point();
    match r.below(5) {
        0 => Shape::Sphere {
            center: p,
            radius: r.range(0.1, 1.5),
        },
        1 => {
            // Axis-aligned half the time (flat bounds, as walls).
            let (u, v) = if r.f() < 0.5 {
                let a = r.below(3);
                let (mut u, mut v) = (DVec3::ZERO, DVec3::ZERO);
                u[a] = r.range(0.5, 3.0);
                v[(a + 1) % 3] = r.range(0.5, 3.0);
                (u, v)
            } else {
                (r.dir() * 2.0, r.dir() * 2.0)
            };
            Shape::Quad {
                vertices: [p, p + u, p + u + v, p + v],
                normal: u.cross(v).normalize(),
            }
        }
        2 => {
            let q = p + DVec3::new(r.range(0.1, 2.0), r.range(0.1, 2.0), r.range(0.1, 2.0));
            let q = if r.f() < 0.5 {
                (q * 2.0).round() / 2.0
            } else {
                q
            };
            Shape::Box {
                min: p,
                max: q.max(p + 0.1),
            }
        }
        3 => {
            let (b, c) = (p + r.dir() * 2.0, p + r.dir() * 2.0);
            Shape::Triangle {
                vertices: [p, b, c],
                normal: (b - p).cross(c - p).normalize(),
            }
        }
        _ => {
            let mut n = DVec3::ZERO;
            n[r.below(3)] = if r.f() < 0.5 { 1.0 } else { -1.0 };
            Shape::Plane {
                point: p - 3.0 * n,
                normal: n,
            }
        }
    }
}

fn scene(r: &mut Rng, n: usize) -> Scene {
    let mut s = Scene::default_scene();
    let mut objects: Vec<Object> = Vec::new();
    while objects.len() < n {
        // Duplicates: ties broken by the lowest index.
        let shape = if !objects.is_empty() && r.f() < 0.2 {
            objects[r.below(objects.len())].shape.clone()
        } else {
            shape(r)
        };
        if let Shape::Triangle { normal, .. } | Shape::Quad { normal, .. } = shape
            && !normal.is_finite()
        {
            continue;
        }
        objects.push(Object {
            name: format!("o{}", objects.len()),
            shape,
            material: 0,
        });
    }
    s.objects = objects;
    s.rebuild_accel();
    s
}

/// A ray from anywhere: random, along an axis, or through a corner or edge of an object.
fn ray(r: &mut Rng, s: &Scene) -> (Ray, f64) {
    let o = DVec3::new(r.range(-6.0, 6.0), r.range(-6.0, 6.0), r.range(-6.0, 6.0));
    let d = match r.below(4) {
        0 => {
            let mut d = DVec3::ZERO;
            d[r.below(3)] = if r.f() < 0.5 { 1.0 } else { -1.0 };
            d
        }
        1 => {
            let target = match s.objects[r.below(s.objects.len())].shape {
                Shape::Quad { vertices, .. } => {
                    let k = r.below(4);
                    vertices[k].lerp(vertices[(k + 1) % 4], r.f().round())
                }
                Shape::Triangle { vertices, .. } => vertices[r.below(3)],
                Shape::Box { min, max } => min.lerp(max, r.f().round()),
                Shape::Sphere { center, .. } | Shape::Plane { point: center, .. } => center,
                Shape::Mesh(_) => DVec3::ZERO,
            };
            target - o
        }
        _ => r.dir(),
    };
    let t_min = if r.f() < 0.5 { 0.0 } else { 1e-9 };
    let t_max = if r.f() < 0.7 {
        f64::INFINITY
    } else {
        r.range(0.0, 10.0)
    };
    (Ray::new(o, d, t_min), t_max)
}

/// The reference: every object's [`Shape::intersect`] in object order.
fn linear(s: &Scene, ray: &Ray, t_max: f64) -> Option<(f64, usize, DVec3)> {
    let (mut best, mut t_max) = (None, t_max);
    for (i, o) in s.objects.iter().enumerate() {
        if let Some(h) = o.shape.intersect(ray, t_max) {
            t_max = h.t;
            best = Some((h.t, i, h.normal));
        }
    }
    best
}

#[test]
fn queries_equal_the_linear_scan() {
    let mut r = Rng(7);
    let (mut hits, mut ties) = (0, 0);
    for k in 0..300 {
        // 1..=48 objects: the small scan, and the BVH beyond SMALL_MAX bounded objects.
        let s = scene(&mut r, 1 + k % 48);
        for _ in 0..200 {
            let (ray, t_max) = ray(&mut r, &s);
            let want = linear(&s, &ray, t_max);
            let got = s.intersect_counted(&ray, t_max, &mut TraversalCost::default());
            let got = got.map(|h| (h.t, h.object, h.normal));
            assert_eq!(
                want.map(|(t, i, n)| (t.to_bits(), i, n.to_array().map(f64::to_bits))),
                got.map(|(t, i, n)| (t.to_bits(), i, n.to_array().map(f64::to_bits))),
                "scene {k}, {ray:?}, t_max {t_max}"
            );
            let blocked = s.occluded(&ray, t_max, &mut TraversalCost::default());
            assert_eq!(blocked, want.is_some(), "scene {k}, {ray:?}, t_max {t_max}");
            if let Some((t, i, _)) = want {
                hits += 1;
                ties += usize::from(s.objects[..i].iter().any(|o| {
                    o.shape
                        .intersect(&ray, f64::INFINITY)
                        .is_some_and(|h| h.t == t)
                })) + usize::from(s.objects[i + 1..].iter().any(|o| {
                    o.shape
                        .intersect(&ray, f64::INFINITY)
                        .is_some_and(|h| h.t == t)
                }));
            }
        }
    }
    // The scenes exercise what they are for: many hits, and ties among them.
    assert!(hits > 20_000 && ties > 1_000, "{hits} hits, {ties} ties");
}

/// `Scene::object_t` (the emitter's own test that shortens a shadow ray) is the distance of
/// `Shape::intersect` on that object alone, bit for bit, with and without a prepared scene.
#[test]
fn object_t_is_the_shapes_own_distance() {
    let mut r = Rng(11);
    let mut hits = 0;
    for k in 0..100 {
        let mut s = scene(&mut r, 1 + k % 40);
        for _ in 0..100 {
            let (ray, t_max) = ray(&mut r, &s);
            for (i, o) in s.objects.iter().enumerate() {
                let want = o.shape.intersect(&ray, t_max).map(|h| h.t.to_bits());
                assert_eq!(
                    s.object_t(i, &ray, t_max).map(f64::to_bits),
                    want,
                    "{k} {i}"
                );
                hits += usize::from(want.is_some());
            }
        }
        // An edited scene (no rebuild): the shapes' own tests.
        if s.objects.len() < 2 {
            continue;
        }
        s.objects.pop();
        let (ray, t_max) = ray(&mut r, &s);
        for (i, o) in s.objects.iter().enumerate() {
            let want = o.shape.intersect(&ray, t_max).map(|h| h.t.to_bits());
            assert_eq!(s.object_t(i, &ray, t_max).map(f64::to_bits), want);
        }
    }
    assert!(hits > 1_000, "{hits}");
}

/// The point of the bounds: in a small scene most rays run far fewer exact tests than there
/// are objects (a linear scan runs all of them).
#[test]
fn small_scenes_test_few_objects() {
    let mut r = Rng(11);
    let (mut prims, mut rays) = (0u64, 0u64);
    for _ in 0..50 {
        let s = scene(&mut r, 16);
        for _ in 0..100 {
            let (ray, t_max) = ray(&mut r, &s);
            let mut cost = TraversalCost::default();
            let _ = s.intersect_counted(&ray, t_max, &mut cost);
            assert_eq!(
                cost.nodes as usize,
                s.objects.len() - s.accel.planes.len() - s.accel.spheres.len()
            );
            prims += u64::from(cost.prims);
            rays += 1;
        }
    }
    assert!(
        prims * 2 < rays * 16,
        "{prims} exact tests for {rays} rays over 16 objects"
    );
}

/// The Cornell box's floor (object 0) and left wall (object 3) meet on the line `x = -1`,
/// `y = 0`; this camera ray hits both there at the same distance. The floor must win (lowest
/// index), as in the linear scan. With the candidates sorted by entry distance and boxes
/// padded per axis (none across a flat quad at `y = 0`), the floor's entry rounded above the
/// hit and the wall won; candidates are now tried in object order, so this ray passes with
/// either padding (`shared_edges_tie_as_the_linear_scan` is the one the padding fails).
#[test]
fn corner_tie_goes_to_the_lowest_index() {
    let src = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/fixtures/cornell-box.json"
    ))
    .expect("fixture");
    let s = Scene::from_json(&src).expect("valid");
    let ray = Ray::new(
        DVec3::new(0.0, 1.0, 3.4),
        DVec3::new(
            -0.2323110206915809,
            -0.2323110206915809,
            -0.9444909630750692,
        ),
        0.0,
    );
    let want = linear(&s, &ray, f64::INFINITY).expect("a hit");
    assert_eq!((want.0, want.1), (4.304574087888894, 0));
    let wall = s.objects[3]
        .shape
        .intersect(&ray, f64::INFINITY)
        .expect("a hit");
    assert_eq!(wall.t, want.0, "a tie");
    let got = s.intersect(&ray, f64::INFINITY).expect("a hit");
    assert_eq!((got.t, got.object, got.normal), want);
}

/// Rooms of axis-aligned quads on the planes `x, y, z in {-1, 0, 1}` (walls that share edges,
/// some through zero, where a per-axis padding gives a flat box no thickness), boxes and
/// duplicates (every other room with distant spheres enough for the object BVH), and rays from grid points to points on the shared edges: closest hit and
/// any-hit as the linear scan, ties (both quads of an edge hit at one distance) included.
#[test]
fn shared_edges_tie_as_the_linear_scan() {
    let mut r = Rng(3);
    let (mut ties, mut rays) = (0, 0);
    for room in 0..80 {
        let mut s = Scene::default_scene();
        let mut objects = Vec::new();
        let grid = |r: &mut Rng| f64::from(r.below(3) as i32 - 1);
        for _ in 0..12 {
            let a = r.below(3);
            let mut p = DVec3::new(grid(&mut r), grid(&mut r), grid(&mut r));
            p[(a + 1) % 3] = p[(a + 1) % 3].min(0.0);
            p[(a + 2) % 3] = p[(a + 2) % 3].min(0.0);
            let (mut u, mut v) = (DVec3::ZERO, DVec3::ZERO);
            u[(a + 1) % 3] = 1.0;
            v[(a + 2) % 3] = 1.0;
            let (u, v) = if r.f() < 0.5 { (u, v) } else { (v, u) };
            objects.push(Shape::Quad {
                vertices: [p, p + u, p + u + v, p + v],
                normal: u.cross(v),
            });
        }
        objects.push(Shape::Box {
            min: DVec3::splat(-1.0),
            max: DVec3::ZERO,
        });
        for k in [3, 7] {
            objects.insert(k, objects[r.below(objects.len())].clone());
        }
        // Every other room out of the small scan's reach: the object BVH serves it.
        if room % 2 == 1 {
            for k in 0..SMALL_MAX {
                objects.push(Shape::Sphere {
                    center: DVec3::new(50.0 + 3.0 * k as f64, 0.0, 0.0),
                    radius: 1.0,
                });
            }
        }
        s.objects = (objects.into_iter().enumerate())
            .map(|(i, shape)| Object {
                name: format!("o{i}"),
                shape,
                material: 0,
            })
            .collect();
        s.rebuild_accel();
        for _ in 0..400 {
            let o = DVec3::new(grid(&mut r), grid(&mut r), grid(&mut r)) * 3.0
                + DVec3::new(0.5, 0.25, 0.125);
            let Shape::Quad { vertices, .. } = s.objects[r.below(12)].shape else {
                continue;
            };
            let k = r.below(4);
            let target = vertices[k].lerp(vertices[(k + 1) % 4], r.f());
            let ray = Ray::new(o, target - o, 0.0);
            let want = linear(&s, &ray, f64::INFINITY);
            let got = s.intersect(&ray, f64::INFINITY);
            assert_eq!(
                want.map(|(t, i, _)| (t, i)),
                got.map(|h| (h.t, h.object)),
                "{ray:?}"
            );
            let tie = want.is_some_and(|(t, i, _)| {
                s.objects[i + 1..].iter().any(|o| {
                    o.shape
                        .intersect(&ray, f64::INFINITY)
                        .is_some_and(|h| h.t == t)
                })
            });
            ties += usize::from(tie);
            rays += 1;
        }
    }
    assert!(ties > rays / 20, "{ties} ties in {rays} rays");
}
