//! Ray–primitive geometry: watertightness on closed meshes, robustness at grazing angles and far away, the origin
//! offset against self-intersection (shadow acne) and light leaking, optics identities.

use glam::Vec3A;
use prism::geometry::{Ray, TriPacket, WatertightRay, gamma, intersect_sphere, offset_ray_origin, spawn_ray};
use prism::math::{Frame, floor_f32, fresnel_dielectric, lane_mask16, refract};
use prism::mesh::MeshData;
use prism::primitives::sphere_point_error;
use prism::sampling::{Rng, warp};

/// A closed triangle mesh: an icosphere (subdivided octahedron, projected) with shared vertices.
fn closed_mesh(level: u32) -> Vec<[Vec3A; 3]> {
    let v = [Vec3A::X, -Vec3A::X, Vec3A::Y, -Vec3A::Y, Vec3A::Z, -Vec3A::Z];
    let mut tris: Vec<[Vec3A; 3]> = vec![
        [v[0], v[2], v[4]],
        [v[2], v[1], v[4]],
        [v[1], v[3], v[4]],
        [v[3], v[0], v[4]],
        [v[2], v[0], v[5]],
        [v[1], v[2], v[5]],
        [v[3], v[1], v[5]],
        [v[0], v[3], v[5]],
    ];
    for _ in 0..level {
        let mut next = Vec::new();
        for [a, b, c] in tris {
            let (ab, bc, ca) = ((a + b).normalize(), (b + c).normalize(), (c + a).normalize());
            next.extend([[a, ab, ca], [ab, b, bc], [ca, bc, c], [ab, bc, ca]]);
        }
        tris = next;
    }
    tris
}

fn hits_any(tris: &[[Vec3A; 3]], ray: &Ray) -> bool {
    let wt = WatertightRay::new(ray);
    tris.iter().any(|t| wt.intersect(t[0], t[1], t[2], ray.tmax).is_some())
}

#[test]
fn watertight_rays_from_inside_a_closed_mesh_always_hit_even_through_vertices_and_edges() {
    let tris = closed_mesh(3);
    let mut dirs: Vec<Vec3A> = Vec::new();
    // Exactly through every vertex and every edge midpoint (the hard cases for non-watertight tests) ...
    for t in &tris {
        for i in 0..3 {
            dirs.push(t[i].normalize());
            dirs.push((t[i] + t[(i + 1) % 3]).normalize());
        }
    }
    // ... and many random directions.
    let mut rng = Rng::new(7, 1);
    dirs.extend((0..20000).map(|_| warp::uniform_sphere(rng.next_2d())));
    let origins = [Vec3A::ZERO, Vec3A::new(0.1, -0.2, 0.05), Vec3A::new(1e-4, 0.0, 0.0)];
    let mut misses = 0;
    for o in origins {
        for d in &dirs {
            if !hits_any(&tris, &Ray::new(o, *d)) {
                misses += 1;
            }
        }
    }
    assert_eq!(misses, 0, "rays escaped a closed mesh through cracks");
}

#[test]
fn watertight_rays_through_shared_edges_of_a_planar_fan_never_fall_through() {
    // A fan of triangles around the origin in the z = 0 plane; rays straight down exactly along shared edges.
    let n = 12;
    let tris: Vec<[Vec3A; 3]> = (0..n)
        .map(|i| {
            let a0 = i as f32 / n as f32 * std::f32::consts::TAU;
            let a1 = (i + 1) as f32 / n as f32 * std::f32::consts::TAU;
            [Vec3A::ZERO, Vec3A::new(a0.cos(), a0.sin(), 0.0), Vec3A::new(a1.cos(), a1.sin(), 0.0)]
        })
        .collect();
    for i in 0..n {
        let a = i as f32 / n as f32 * std::f32::consts::TAU;
        for r in [0.0, 0.25, 0.5, 0.9] {
            let o = Vec3A::new(r * a.cos(), r * a.sin(), 1.0);
            assert!(hits_any(&tris, &Ray::new(o, -Vec3A::Z)), "fell through at edge {i}, r = {r}");
        }
    }
}

#[test]
fn packet_prefilter_never_rejects_a_triangle_the_exact_watertight_test_hits() {
    // The kd-tree tests leaf triangles four at a time with an edge-function pre-filter and only runs the exact
    // test on survivors: a rejected lane that the exact test would hit would be a hole in the mesh. Rays from
    // inside and outside a closed mesh, exactly through its vertices and edge midpoints (zero edge functions) and
    // in random directions, over packets of four of its triangles.
    let tris = closed_mesh(2);
    let mut rng = Rng::new(11, 3);
    let mut rays = Vec::new();
    for t in &tris {
        for i in 0..3 {
            for o in [Vec3A::ZERO, Vec3A::new(0.1, -0.2, 0.05)] {
                rays.push(Ray::new(o, (t[i] - o).normalize()));
                rays.push(Ray::new(o, ((t[i] + t[(i + 1) % 3]) * 0.5 - o).normalize()));
            }
            let outside = t[i] * 3.0;
            rays.push(Ray::new(outside, (t[(i + 1) % 3] - outside).normalize()));
        }
    }
    for _ in 0..5000 {
        let o = warp::uniform_sphere(rng.next_2d()) * (0.5 + 3.0 * rng.next_f32());
        rays.push(Ray::new(o, warp::uniform_sphere(rng.next_2d())));
    }
    let (mut exact_hits, mut survivors) = (0, 0);
    for ray in &rays {
        let wt = WatertightRay::new(ray);
        for chunk in tris.chunks(4) {
            let packet = TriPacket::new(chunk);
            let candidates = wt.packet_candidates(&packet);
            for (lane, t) in chunk.iter().enumerate() {
                assert_eq!(packet.lane(lane).vertices(), *t, "packet lane {lane} does not hold its triangle");
                let hit = wt.intersect(t[0], t[1], t[2], f32::INFINITY).is_some();
                exact_hits += hit as u32;
                survivors += candidates >> lane & 1;
                assert!(!hit || candidates >> lane & 1 == 1, "pre-filter rejected a hit: ray {ray:?}, lane {lane}");
            }
        }
    }
    // The filter must also do its job: most lanes rejected.
    let lanes = (rays.len() * tris.len()) as u32;
    assert!(exact_hits > 0 && survivors < lanes / 4, "{survivors} of {lanes} lanes survived ({exact_hits} hits)");
}

/// The BVH's leaves test a packet's surviving lanes with `intersect_packet`, the whole watertight test four lanes
/// at once; it must give exactly what the scalar kernel gives called on those lanes in order, each call's `tmax`
/// the hit found so far: the same lane, `t` and barycentrics bit for bit. Rays through the vertices and edges of a
/// closed mesh (zero edge functions: the double-precision fallback), random rays, random `tmax` (cutting hits
/// off), and packets holding the same triangle twice or a coplanar copy (exact ties: the lower lane wins).
#[test]
fn a_packets_whole_watertight_test_equals_the_scalar_kernel_lane_after_lane() {
    let mut tris = closed_mesh(2);
    // Ties: a triangle twice in one packet, and one moved within its own plane.
    let (a, b) = (tris[5], tris[9]);
    assert_eq!(tris.len() % 4, 0, "the tie packets must start on a packet boundary");
    let shift = (a[1] - a[0]) * 0.25;
    tris.extend([a, b, a, b]);
    tris.extend([[a[0] + shift, a[1] + shift, a[2] + shift], a, b, b]);
    let mut rng = Rng::new(21, 5);
    let mut rays = Vec::new();
    for t in &tris {
        for i in 0..3 {
            let o = Vec3A::new(0.1, -0.2, 0.05);
            rays.push(Ray::new(o, (t[i] - o).normalize()));
            rays.push(Ray::new(o, ((t[i] + t[(i + 1) % 3]) * 0.5 - o).normalize()));
        }
    }
    for _ in 0..4000 {
        let o = warp::uniform_sphere(rng.next_2d()) * (0.5 + 3.0 * rng.next_f32());
        rays.push(Ray::new(o, warp::uniform_sphere(rng.next_2d())));
    }
    let bits = |(k, h): (usize, prism::geometry::TriangleHit)| (k, [h.t, h.b0, h.b1, h.b2].map(f32::to_bits));
    let mut hits = 0;
    for ray in &rays {
        let wt = WatertightRay::new(ray);
        for chunk in tris.chunks(4) {
            let packet = TriPacket::new(chunk);
            for tmax in [f32::INFINITY, 0.5 + 3.0 * rng.next_f32()] {
                for lanes in [(1u32 << chunk.len()) - 1, rng.next_u32() & ((1 << chunk.len()) - 1)] {
                    let mut end = tmax;
                    let mut expected = None;
                    for k in (0..chunk.len()).filter(|k| lanes >> k & 1 == 1) {
                        if let Some(h) = wt.intersect_soa(&packet.lane(k), end) {
                            end = h.t;
                            expected = Some((k, h));
                        }
                    }
                    let got = wt.intersect_packet(&packet, lanes, tmax);
                    assert_eq!(got.map(bits), expected.map(bits), "ray {ray:?}, lanes {lanes:#b}, tmax {tmax}");
                    hits += expected.is_some() as u32;
                }
            }
        }
    }
    assert!(hits > 1000, "too few hits ({hits}) for the test to mean anything");
}

/// The watertight test as Woop, Benthin & Wald write it, each vertex less the origin multiplied by the full
/// shear/permutation matrix (`WatertightRay::coefficients`: three products and two sums per coordinate), with
/// pbrt-v4's rounding-error bound on `t`: the reference for the kernel, which maps a vertex by `d[kx] - sx d[kz]`,
/// `d[ky] - sy d[kz]`, `sz d[kz]` and must get the same numbers.
fn watertight_by_matrix(wt: &WatertightRay, v: [Vec3A; 3], tmax: f32) -> Option<[f32; 4]> {
    let (o, rows) = wt.coefficients();
    let map = |r: usize, p: Vec3A| {
        let d = [p.x - o[0], p.y - o[1], p.z - o[2]];
        d[0] * rows[r][0] + d[1] * rows[r][1] + d[2] * rows[r][2]
    };
    let (x, y, z) = (v.map(|p| map(0, p)), v.map(|p| map(1, p)), v.map(|p| map(2, p)));
    let mut e = [x[2] * y[1] - y[2] * x[1], x[0] * y[2] - y[0] * x[2], x[1] * y[0] - y[1] * x[0]];
    if e.contains(&0.0) {
        let (x, y) = (x.map(f64::from), y.map(f64::from));
        e = [
            (x[2] * y[1] - y[2] * x[1]) as f32,
            (x[0] * y[2] - y[0] * x[2]) as f32,
            (x[1] * y[0] - y[1] * x[0]) as f32,
        ];
    }
    if e.iter().any(|&a| a < 0.0) && e.iter().any(|&a| a > 0.0) {
        return None;
    }
    let det = e[0] + e[1] + e[2];
    if det == 0.0 {
        return None;
    }
    let ts = e[0] * z[0] + e[1] * z[1] + e[2] * z[2];
    let out = if det > 0.0 { ts <= 0.0 || ts >= tmax * det } else { ts >= 0.0 || ts <= tmax * det };
    if out {
        return None;
    }
    let inv = 1.0 / det;
    let t = ts * inv;
    let amax = |a: [f32; 3]| a[0].abs().max(a[1].abs()).max(a[2].abs());
    let (max_zt, max_xt, max_yt, max_e) = (amax(z), amax(x), amax(y), amax(e));
    let delta_z = gamma(3) * max_zt;
    let delta_x = gamma(5) * (max_xt + max_zt);
    let delta_y = gamma(5) * (max_yt + max_zt);
    let delta_e = 2.0 * (gamma(2) * max_xt * max_yt + delta_y * max_xt + delta_x * max_yt);
    let delta_t = 3.0 * (gamma(3) * max_e * max_zt + delta_e * max_zt + delta_z * max_e) * inv.abs();
    if t <= delta_t {
        return None;
    }
    Some([t, e[0] * inv, e[1] * inv, e[2] * inv])
}

/// The kernel's shear leaves out the matrix's zero and unit coefficients (two operations per coordinate instead of
/// five): a product by 0 or 1 and a sum with zero are exact, so every hit, `t` and barycentric must be the matrix
/// form's, bit for bit (a zero barycentric may differ in its sign only). Rays along and against every axis and
/// diagonal (each permutation and sign of the largest component, ties between components), through the vertices
/// and edges of a closed mesh (zero edge functions: the double-precision fallback), and random; and packets of four
/// triangles, whose pre-filter and whole test take the same shortcut, against the same reference.
#[test]
fn the_kernels_shear_computes_the_full_matrix_product_bit_for_bit() {
    let tris = closed_mesh(2);
    let mut rng = Rng::new(31, 7);
    let mut dirs: Vec<Vec3A> = vec![];
    for a in [-1.0f32, 0.0, 1.0] {
        for b in [-1.0f32, 0.0, 1.0] {
            for c in [-1.0f32, 0.0, 1.0] {
                if (a, b, c) != (0.0, 0.0, 0.0) {
                    dirs.push(Vec3A::new(a, b, c).normalize());
                }
            }
        }
    }
    let mut rays: Vec<Ray> = vec![];
    for o in [Vec3A::new(0.1, -0.2, 0.05), Vec3A::new(-0.3, 0.25, 0.4)] {
        rays.extend(dirs.iter().map(|&d| Ray::new(o, d)));
        for t in &tris {
            rays.push(Ray::new(o, (t[0] - o).normalize()));
            rays.push(Ray::new(o, ((t[1] + t[2]) * 0.5 - o).normalize()));
        }
    }
    for _ in 0..3000 {
        let o = warp::uniform_sphere(rng.next_2d()) * (0.5 + 3.0 * rng.next_f32());
        rays.push(Ray::new(o, warp::uniform_sphere(rng.next_2d())));
    }
    let same = |got: Option<[f32; 4]>, want: Option<[f32; 4]>| match (got, want) {
        (Some(g), Some(w)) => g[0].to_bits() == w[0].to_bits() && g[1..] == w[1..],
        (g, w) => g.is_none() && w.is_none(),
    };
    let mut hits = 0;
    for ray in &rays {
        let wt = WatertightRay::new(ray);
        for chunk in tris.chunks(4) {
            let packet = TriPacket::new(chunk);
            let candidates = wt.packet_candidates(&packet);
            for (k, t) in chunk.iter().enumerate() {
                let want = watertight_by_matrix(&wt, *t, f32::INFINITY);
                let got = wt.intersect(t[0], t[1], t[2], f32::INFINITY).map(|h| [h.t, h.b0, h.b1, h.b2]);
                assert!(same(got, want), "ray {ray:?}, triangle {t:?}: kernel {got:?}, matrix {want:?}");
                let lane = wt.intersect_packet(&packet, 1 << k, f32::INFINITY).map(|(_, h)| [h.t, h.b0, h.b1, h.b2]);
                assert!(same(lane, want), "ray {ray:?}, packet lane {k}: {lane:?}, matrix {want:?}");
                assert!(want.is_none() || candidates >> k & 1 == 1, "pre-filter rejected a hit: ray {ray:?}");
                hits += want.is_some() as u32;
            }
        }
    }
    assert!(hits > 1000, "too few hits ({hits}) for the test to mean anything");
}

#[test]
fn triangle_barycentrics_reconstruct_the_hit_point() {
    let (p0, p1, p2) = (Vec3A::new(0., 0., 0.), Vec3A::new(2., 0., 0.), Vec3A::new(0., 3., 1.));
    let mut rng = Rng::new(3, 3);
    for _ in 0..1000 {
        let (b0, b1, b2) = warp::uniform_triangle(rng.next_2d());
        let target = b0 * p0 + b1 * p1 + b2 * p2;
        let o = Vec3A::new(0.3, -2.0, 4.0);
        let ray = Ray::new(o, (target - o).normalize());
        let h = WatertightRay::new(&ray).intersect(p0, p1, p2, f32::INFINITY).expect("hit");
        let p = h.b0 * p0 + h.b1 * p1 + h.b2 * p2;
        assert!((p - target).length() < 1e-5);
        assert!((ray.at(h.t) - target).length() < 1e-4);
        assert!((h.b0 + h.b1 + h.b2 - 1.0).abs() < 1e-5);
    }
}

#[test]
fn sphere_intersection_is_accurate_for_far_rays_and_large_spheres() {
    // A unit sphere seen from 1e4 away: the hit must lie on the sphere to float precision of the sphere's scale.
    let c = Vec3A::new(0.0, 0.0, 0.0);
    let o = Vec3A::new(1.0e4, 0.3, -0.2);
    let target = Vec3A::new(0.6, 0.0, 0.8);
    let d = (target - o).normalize();
    let t = intersect_sphere(c, 1.0, o, d, f32::INFINITY).unwrap();
    let p = o + d * t;
    assert!((p.length() - 1.0).abs() < 2e-3, "hit {p:?} not on the sphere");
    // A huge sphere (radius 1e5), ray from just outside.
    let t = intersect_sphere(Vec3A::ZERO, 1.0e5, Vec3A::new(0.0, 1.0e5 + 1.0, 0.0), -Vec3A::Y, f32::INFINITY).unwrap();
    assert!((t - 1.0).abs() < 0.02, "t = {t}");
    // Non-unit direction: t is in units of the direction (object-space intersection of transformed spheres).
    let t2 = intersect_sphere(Vec3A::ZERO, 1.0, Vec3A::new(0.0, 0.0, 5.0), Vec3A::new(0.0, 0.0, -2.0), f32::INFINITY);
    assert!((t2.unwrap() - 2.0).abs() < 1e-5);
}

#[test]
fn offset_origins_do_not_self_intersect_at_grazing_angles_on_spheres_of_any_scale() {
    // Shadow acne test: from points on a sphere, rays leaving at grazing angles (1e-3 rad above the tangent plane)
    // must not re-hit the sphere; rays entering must hit the far side, not the near point again.
    let mut rng = Rng::new(11, 2);
    for scale in [1e-3f32, 1.0, 1e3, 1e5] {
        let mut acne = 0;
        for _ in 0..2000 {
            let n = warp::uniform_sphere(rng.next_2d());
            let p = n * scale;
            let f = Frame::from_normal(n);
            let phi = rng.next_f32() * std::f32::consts::TAU;
            let grazing = 1e-3f32;
            let out = f.to_world(Vec3A::new(grazing.cos() * phi.cos(), grazing.cos() * phi.sin(), grazing.sin()));
            let err = sphere_point_error(Vec3A::ZERO, p, None);
            let ray = spawn_ray(p, err, n, out);
            if intersect_sphere(Vec3A::ZERO, scale, ray.origin, ray.dir, f32::INFINITY).is_some() {
                acne += 1;
            }
            // Inward ray: the next hit is the far side, at distance 2 r cos(theta) > 0.
            let ray = spawn_ray(p, err, n, -n);
            let t = intersect_sphere(Vec3A::ZERO, scale, ray.origin, ray.dir, f32::INFINITY).expect("far side");
            assert!((t - 2.0 * scale).abs() < 1e-5 * scale, "scale {scale}: far-side t {t}");
        }
        assert_eq!(acne, 0, "scale {scale}: grazing rays re-hit their own sphere");
    }
}

#[test]
fn offset_is_proportional_to_the_rounding_error_so_thin_walls_do_not_leak() {
    // Two parallel quads 1e-4 apart (a thin wall); a ray spawned from the first towards the second must hit it.
    let wall = MeshData::unit_quad();
    let tri = |z: f32| -> Vec<[Vec3A; 3]> {
        wall.indices
            .iter()
            .map(|i| i.map(|k| Vec3A::from(wall.positions[k as usize]) + Vec3A::new(0., 0., z)))
            .collect()
    };
    let back = tri(-1e-4);
    let mut rng = Rng::new(5, 5);
    for _ in 0..1000 {
        let p = Vec3A::new(rng.next_f32() * 1.6 - 0.8, rng.next_f32() * 1.6 - 0.8, 0.0);
        let ray = spawn_ray(p, gamma(7) * p.abs(), Vec3A::Z, -Vec3A::Z);
        // The hit point of an axis-aligned wall is exact in z: no offset is needed and none is applied.
        assert!(ray.origin.z <= 0.0 && ray.origin.z > -1e-6, "offset moved too far: {:?}", ray.origin);
        assert!(hits_any(&back, &ray), "ray leaked through a 1e-4 thick wall");
    }
    // The offset scales with the coordinates' magnitude: a few ULPs, at 1e-3 and at 1e5 alike.
    for mag in [1e-3f32, 1.0, 1e5] {
        let p = Vec3A::new(mag, 0.0, 0.0);
        let o = offset_ray_origin(p, gamma(7) * p.abs(), Vec3A::X, Vec3A::X);
        let ulps = o.x.to_bits() - mag.to_bits();
        assert!((1..=8).contains(&ulps), "offset at magnitude {mag} is {ulps} ulps");
    }
}

/// pbrt-v4's `OffsetRayOrigin` written coordinate by coordinate with its `NextFloatUp` / `NextFloatDown` branches:
/// the reference for the renderer's version, which rounds the four lanes at once with masks.
fn offset_by_branches(p: Vec3A, p_err: Vec3A, n: Vec3A, w: Vec3A) -> Vec3A {
    fn next_up(v: f32) -> f32 {
        if v.is_infinite() && v > 0.0 {
            return v;
        }
        let v = if v == -0.0 { 0.0 } else { v };
        f32::from_bits(if v >= 0.0 { v.to_bits() + 1 } else { v.to_bits() - 1 })
    }
    fn next_down(v: f32) -> f32 {
        if v.is_infinite() && v < 0.0 {
            return v;
        }
        let v = if v == 0.0 { -0.0 } else { v };
        f32::from_bits(if v > 0.0 { v.to_bits() - 1 } else { v.to_bits() + 1 })
    }
    let d = n.abs().dot(p_err);
    let mut offset = n * d;
    if w.dot(n) < 0.0 {
        offset = -offset;
    }
    let po = p + offset;
    let round = |v: f32, o: f32| {
        if o > 0.0 {
            next_up(v)
        } else if o < 0.0 {
            next_down(v)
        } else {
            v
        }
    };
    Vec3A::new(round(po.x, offset.x), round(po.y, offset.y), round(po.z, offset.z))
}

#[test]
fn offset_origins_round_outward_exactly_as_pbrts_next_float_up_and_down() {
    // Every sign and kind of coordinate (zeros of both signs, the smallest denormals, infinities, NaN, the largest
    // finite values) against offsets of every sign, zero offsets of both signs included: the renderer's mask form
    // must give pbrt's branchy result bit for bit, or a spawned ray could start inside its surface.
    let specials = [
        0.0,
        -0.0,
        f32::from_bits(1),
        -f32::from_bits(1),
        1.0,
        -1.0,
        0.3,
        -7.5e4,
        f32::MAX,
        f32::MIN,
        f32::INFINITY,
        f32::NEG_INFINITY,
        f32::NAN,
    ];
    let normals = [Vec3A::X, -Vec3A::Y, Vec3A::Z, Vec3A::new(0.6, -0.8, 0.0), Vec3A::new(-0.0, 0.6, 0.8)];
    let errors = [Vec3A::ZERO, Vec3A::splat(1e-7), Vec3A::new(0.0, 3e-6, f32::from_bits(1))];
    let mut rng = Rng::new(17, 3);
    let mut cases = 0;
    for &x in &specials {
        for &y in &specials {
            let p = Vec3A::new(x, y, specials[cases % specials.len()]);
            for &n in &normals {
                for &p_err in &errors {
                    for w in [n, -n, Vec3A::new(n.y, -n.x, 0.0), Vec3A::new(-n.y, n.x, -0.0)] {
                        let got = offset_ray_origin(p, p_err, n, w);
                        let want = offset_by_branches(p, p_err, n, w);
                        for k in 0..3 {
                            assert_eq!(
                                got[k].to_bits(),
                                want[k].to_bits(),
                                "coordinate {k} of p {p:?}, error {p_err:?}, normal {n:?}, side {w:?}"
                            );
                        }
                        cases += 1;
                    }
                }
            }
        }
    }
    for _ in 0..20_000 {
        let mut v = || (rng.next_f32() - 0.5) * 10f32.powi((rng.next_f32() * 12.0) as i32 - 6);
        let p = Vec3A::new(v(), v(), v());
        let n = Vec3A::new(v(), v(), v()).normalize_or(Vec3A::Z);
        let w = Vec3A::new(v(), v(), v());
        let got = offset_ray_origin(p, gamma(7) * p.abs(), n, w);
        let want = offset_by_branches(p, gamma(7) * p.abs(), n, w);
        assert_eq!(got.to_array().map(f32::to_bits), want.to_array().map(f32::to_bits), "p {p:?}, n {n:?}");
    }
    assert!(cases > 10_000);
}

#[test]
fn fresnel_reflectance_matches_the_closed_form_and_grazing_limit() {
    // Normal incidence: R0 = ((eta - 1) / (eta + 1))^2, from either side; grazing: total reflection.
    let eta = 1.5f32;
    let r0 = ((eta - 1.0) / (eta + 1.0)).powi(2);
    assert!((fresnel_dielectric(1.0, eta) - r0).abs() < 1e-6);
    assert!((fresnel_dielectric(1.0, 1.0 / eta) - r0).abs() < 1e-6);
    assert!((fresnel_dielectric(0.0, eta) - 1.0).abs() < 1e-6);
}

#[test]
fn refraction_obeys_snells_law_and_detects_total_internal_reflection() {
    let n = Vec3A::Z;
    let wo = Vec3A::new(0.6, 0.0, 0.8);
    let wt = refract(wo, n, 1.5).unwrap();
    let sin_t = (wt.x * wt.x + wt.y * wt.y).sqrt() / wt.length();
    assert!((0.6 - 1.5 * sin_t).abs() < 1e-5, "sin_i = eta sin_t");
    assert!(wt.z < 0.0);
    // Glass to air beyond the critical angle asin(1/1.5) = 41.8 deg.
    assert!(refract(Vec3A::new(0.8, 0.0, 0.6), n, 1.0 / 1.5).is_none());
    assert_eq!(fresnel_dielectric(0.6, 1.0 / 1.5), 1.0);
}

#[test]
fn orthonormal_frames_are_right_handed_for_every_normal() {
    let mut rng = Rng::new(1, 9);
    let mut normals: Vec<Vec3A> = (0..1000).map(|_| warp::uniform_sphere(rng.next_2d())).collect();
    normals.extend([Vec3A::Z, -Vec3A::Z, Vec3A::new(-1e-8, 1e-8, -1.0).normalize()]);
    for n in normals {
        let f = Frame::from_normal(n);
        assert!((f.s.length() - 1.0).abs() < 1e-5 && (f.t.length() - 1.0).abs() < 1e-5);
        assert!(f.s.dot(f.t).abs() < 1e-5 && f.s.dot(n).abs() < 1e-5 && f.t.dot(n).abs() < 1e-5);
        assert!((f.s.cross(f.t) - n).length() < 1e-4);
        let v = Vec3A::new(0.3, -0.4, 0.5);
        assert!((f.to_world(f.to_local(v)) - v).length() < 1e-5);
    }
}

#[test]
fn transform_operations_compose_like_matrix_products() {
    use glam::{Affine3A, Vec3};
    use prism::load::compose;
    use prism::load::schema::TransformOp::*;
    let close =
        |a: Affine3A, b: Affine3A| a.to_cols_array().iter().zip(b.to_cols_array()).all(|(x, y)| (x - y).abs() < 1e-5);
    // Euler (x, y, z) degrees = Rz * Ry * Rx.
    let euler = compose(&[Euler([10.0, 20.0, 30.0])], "t").unwrap();
    let chain = compose(
        &[
            Rotate { axis: [0.0, 0.0, 1.0], degrees: 30.0 },
            Rotate { axis: [0.0, 1.0, 0.0], degrees: 20.0 },
            Rotate { axis: [1.0, 0.0, 0.0], degrees: 10.0 },
        ],
        "t",
    )
    .unwrap();
    assert!(close(euler, chain));
    // A row-major matrix equals the TRS it encodes; the list applies left to right as a product.
    let trs = compose(&[Translate([1.0, 2.0, 3.0]), Scale([2.0, 3.0, 4.0])], "t").unwrap();
    let m = compose(
        &[Matrix([[2.0, 0.0, 0.0, 1.0], [0.0, 3.0, 0.0, 2.0], [0.0, 0.0, 4.0, 3.0], [0.0, 0.0, 0.0, 1.0]])],
        "t",
    )
    .unwrap();
    assert!(close(trs, m));
    assert_eq!(trs.transform_point3(Vec3::ONE), Vec3::new(3.0, 5.0, 7.0), "scale first, then translate");
    // Rotation by +90 degrees about x takes +z to -y (right-handed).
    let r = compose(&[Rotate { axis: [1.0, 0.0, 0.0], degrees: 90.0 }], "t").unwrap();
    assert!((r.transform_vector3(Vec3::Z) - Vec3::new(0.0, -1.0, 0.0)).length() < 1e-6);
    assert!(compose(&[UniformScale(0.0)], "t").is_err());
}

/// The ray packets' lane mask, gathered from sixteen 0/1 bytes by two multiplications (`lane_mask16`), is the plain
/// bit-by-bit mask for every one of the 65,536 patterns: the partial products never share a bit, so nothing carries.
#[test]
fn the_multiplied_lane_mask_equals_the_bit_by_bit_mask_for_every_pattern() {
    for pattern in 0u32..1 << 16 {
        let bit = |l: usize| pattern >> l & 1 == 1;
        let plain = (0..16).fold(0u32, |m, l| m | (bit(l) as u32) << l);
        assert_eq!(plain, pattern);
        assert_eq!(lane_mask16(bit), plain, "pattern {pattern:#06x}");
    }
}

/// The call-free floor used by texture and environment lookups is `f32::floor` bit for bit: signed zeros, values
/// just below and above every integer, the 2^23 boundary where every `f32` becomes an integer, infinities, NaN, and
/// a million random bit patterns.
#[test]
fn floor_without_libm_is_f32_floor_bit_for_bit() {
    let same = |x: f32| {
        let (a, b) = (floor_f32(x), x.floor());
        assert!(a.to_bits() == b.to_bits() || (a.is_nan() && b.is_nan()), "floor({x:e}): {a:e} vs {b:e}");
    };
    for x in [0.0, -0.0, 0.5, -0.5, 1.0, -1.0, f32::MIN_POSITIVE, -f32::MIN_POSITIVE, 1e-45, -1e-45] {
        same(x);
    }
    for x in [f32::INFINITY, f32::NEG_INFINITY, f32::NAN, f32::MAX, f32::MIN, 8_388_608.0, -8_388_608.0] {
        same(x);
    }
    for k in -300i32..300 {
        let x = k as f32 * 0.37 + 8_388_000.0 * (k % 3) as f32;
        for y in [x, f32::from_bits(x.to_bits().wrapping_add(1)), f32::from_bits(x.to_bits().wrapping_sub(1))] {
            same(y);
            same(-y);
        }
    }
    for b in [8_388_607.5f32, 8_388_607.0, 4_194_303.5, -4_194_303.5, -8_388_607.5] {
        same(b);
    }
    let mut rng = Rng::new(7, 0);
    for _ in 0..1_000_000 {
        same(f32::from_bits(rng.next_u32()));
    }
}
