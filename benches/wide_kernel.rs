//! How far a wide-SIMD ray kernel is from Prism's one-ray-at-a-time BVH on a tiny scene (`cargo bench --bench
//! wide_kernel`): evidence for `docs/decisions/0020-one-path-at-a-time.md` (no wavefront). An experiment, not a
//! Prism accelerator.
//!
//! On the Cornell box of the Mitsuba comparison (`scenes/cornell_box.ron`, 36 triangles) it takes the ray sets of
//! `prism bench` (camera rays through the 256 x 256 pixel centres, one diffuse bounce from each camera hit), packs
//! them into blocks of 16 rays (structure of arrays, rays across lanes, as a wavefront renderer would hold them)
//! and finds each ray's closest hit by testing all 36 triangles against 16 rays at a time (Moeller-Trumbore, no
//! BVH). The kernel is safe Rust compiled three times by `multiversion` and dispatched at run time (AVX-512,
//! AVX2, baseline SSE2); the same sets go through Prism's BVH one ray at a time (`Accel::intersect`). One thread,
//! 15 interleaved rounds, the best time of each. Printed: Mrays/s of each, the ratio, and on how many rays the
//! kernel's primitive differs from Prism's (the kernel is neither watertight nor error-bounded: edge ties between
//! the two triangles of a quad, and hits within 1e-4 of the origin it skips, account for those).
//!
//! A second kernel, `pluecker`, is watertight: Pluecker edge tests with each edge's direction and moment precomputed
//! (a shared edge gives exactly negated side numbers in its two triangles, as Embree's Pluecker test and Prism's
//! shear-based kernel guarantee), about as cheap per lane as Moeller-Trumbore because the ray's part, `o x d`, is
//! computed once per block. Its columns show whether a wavefront core could keep watertight hits.
//!
//! A third column, the block query, is the Pluecker kernel with conservative rounding bounds (`robust_block.rs`): its
//! sure answers are hits, an unsure ray goes to the tree alone, so it can stand in for the tree; bounce rays name
//! the triangle they leave, as the renderer's do.
//!
//! The kernel is not a drop-in for Prism's traversal: it needs rays sixteen at a time, which is the wavefront
//! redesign decision 0020 did not make, and brute force only pays on scenes this small.

#[path = "wide_kernel/robust_block.rs"]
mod robust_block;

use multiversion::multiversion;
use prism::app::{App, SceneSource};
use prism::geometry::Ray;
use prism::ray_sets::{camera_rays, secondary_rays};
use std::hint::black_box;
use std::path::PathBuf;
use std::time::Instant;

/// Rays per block (lanes).
const LANES: usize = 16;

/// A triangle as Moeller-Trumbore takes it: a vertex and the two edges from it.
struct Tri {
    v0: [f32; 3],
    e1: [f32; 3],
    e2: [f32; 3],
}

/// `LANES` rays, coordinates across lanes.
#[derive(Clone, Copy)]
struct Block {
    o: [[f32; LANES]; 3],
    d: [[f32; LANES]; 3],
    tmax: [f32; LANES],
}

/// The closest hit of every ray of every block: primitive (`u32::MAX` for none) per ray, in block order.
#[multiversion(targets("x86_64+avx512f+avx512vl+avx512dq", "x86_64+avx2+fma"))]
fn closest_dispatched(tris: &[Tri], blocks: &[Block], out: &mut [u32]) {
    closest(tris, blocks, out)
}

#[multiversion(targets("x86_64+avx2+fma"))]
fn closest_avx2(tris: &[Tri], blocks: &[Block], out: &mut [u32]) {
    closest(tris, blocks, out)
}

/// A triangle as the Pluecker test takes it (Embree's `PlueckerIntersector` idea with the moments precomputed): per
/// directed edge `q -> p` (v0 -> v1, v1 -> v2, v2 -> v0) twice its direction `2 (p - q)` and its moment
/// `(p - q) x (p + q)`, and the plane `n . x = n . v0`. A ray's side of an edge is `m . d - 2 e . (o x d)`: a
/// neighbour sharing the edge runs it the other way and computes exactly the negated number (every product and sum
/// negated), so no ray passes between two triangles that share an edge — watertight, like Prism's kernel, without
/// its per-ray shear.
struct Plu {
    e2: [[f32; 3]; 3],
    m: [[f32; 3]; 3],
    n: [f32; 3],
    nv0: f32,
}

fn plu(a: [f32; 3], b: [f32; 3], c: [f32; 3]) -> Plu {
    let sub = |p: [f32; 3], q: [f32; 3]| [p[0] - q[0], p[1] - q[1], p[2] - q[2]];
    let add = |p: [f32; 3], q: [f32; 3]| [p[0] + q[0], p[1] + q[1], p[2] + q[2]];
    let cross =
        |p: [f32; 3], q: [f32; 3]| [p[1] * q[2] - p[2] * q[1], p[2] * q[0] - p[0] * q[2], p[0] * q[1] - p[1] * q[0]];
    let edges = [(a, b), (b, c), (c, a)];
    let e2 = edges.map(|(q, p)| sub(p, q).map(|x| 2.0 * x));
    let m = edges.map(|(q, p)| cross(sub(p, q), add(p, q)));
    let n = cross(sub(b, a), sub(c, a));
    Plu { e2, m, n, nv0: n[0] * a[0] + n[1] * a[1] + n[2] * a[2] }
}

#[multiversion(targets("x86_64+avx512f+avx512vl+avx512dq", "x86_64+avx2+fma"))]
fn pluecker_dispatched(tris: &[Plu], blocks: &[Block], out: &mut [u32]) {
    pluecker(tris, blocks, out)
}

#[inline(always)]
fn pluecker(tris: &[Plu], blocks: &[Block], out: &mut [u32]) {
    for (b, out) in blocks.iter().zip(out.chunks_exact_mut(LANES)) {
        let mut best_t = b.tmax;
        let mut best = [u32::MAX; LANES];
        // o x d per ray, once per block.
        let mut l = [[0.0f32; LANES]; 3];
        #[allow(clippy::needless_range_loop)]
        for k in 0..LANES {
            let (o, d) = ([b.o[0][k], b.o[1][k], b.o[2][k]], [b.d[0][k], b.d[1][k], b.d[2][k]]);
            l[0][k] = o[1] * d[2] - o[2] * d[1];
            l[1][k] = o[2] * d[0] - o[0] * d[2];
            l[2][k] = o[0] * d[1] - o[1] * d[0];
        }
        for (id, t) in tris.iter().enumerate() {
            for k in 0..LANES {
                let (dx, dy, dz) = (b.d[0][k], b.d[1][k], b.d[2][k]);
                let side = |j: usize| {
                    (t.m[j][0] * dx + t.m[j][1] * dy + t.m[j][2] * dz)
                        - (t.e2[j][0] * l[0][k] + t.e2[j][1] * l[1][k] + t.e2[j][2] * l[2][k])
                };
                let (u, v, w) = (side(0), side(1), side(2));
                let den = t.n[0] * dx + t.n[1] * dy + t.n[2] * dz;
                let tt = (t.nv0 - (t.n[0] * b.o[0][k] + t.n[1] * b.o[1][k] + t.n[2] * b.o[2][k])) / den;
                let inside = (u >= 0.0 && v >= 0.0 && w >= 0.0) || (u <= 0.0 && v <= 0.0 && w <= 0.0);
                let hit = inside && den != 0.0 && tt > 1e-4 && tt < best_t[k];
                best_t[k] = if hit { tt } else { best_t[k] };
                best[k] = if hit { id as u32 } else { best[k] };
            }
        }
        out.copy_from_slice(&best);
    }
}

#[inline(never)]
fn closest_baseline(tris: &[Tri], blocks: &[Block], out: &mut [u32]) {
    closest(tris, blocks, out)
}

#[inline(always)]
fn closest(tris: &[Tri], blocks: &[Block], out: &mut [u32]) {
    for (b, out) in blocks.iter().zip(out.chunks_exact_mut(LANES)) {
        let mut best_t = b.tmax;
        let mut best = [u32::MAX; LANES];
        for (id, t) in tris.iter().enumerate() {
            for l in 0..LANES {
                let (dx, dy, dz) = (b.d[0][l], b.d[1][l], b.d[2][l]);
                let (px, py, pz) =
                    (dy * t.e2[2] - dz * t.e2[1], dz * t.e2[0] - dx * t.e2[2], dx * t.e2[1] - dy * t.e2[0]);
                let det = t.e1[0] * px + t.e1[1] * py + t.e1[2] * pz;
                let inv = 1.0 / det;
                let (sx, sy, sz) = (b.o[0][l] - t.v0[0], b.o[1][l] - t.v0[1], b.o[2][l] - t.v0[2]);
                let u = (sx * px + sy * py + sz * pz) * inv;
                let (qx, qy, qz) =
                    (sy * t.e1[2] - sz * t.e1[1], sz * t.e1[0] - sx * t.e1[2], sx * t.e1[1] - sy * t.e1[0]);
                let v = (dx * qx + dy * qy + dz * qz) * inv;
                let tt = (t.e2[0] * qx + t.e2[1] * qy + t.e2[2] * qz) * inv;
                let hit = det != 0.0 && u >= 0.0 && v >= 0.0 && u + v <= 1.0 && tt > 1e-4 && tt < best_t[l];
                best_t[l] = if hit { tt } else { best_t[l] };
                best[l] = if hit { id as u32 } else { best[l] };
            }
        }
        out.copy_from_slice(&best);
    }
}

/// The rays in blocks of `LANES` (a last partial block is dropped).
fn blocks(rays: &[Ray]) -> Vec<Block> {
    rays.chunks_exact(LANES)
        .map(|c| {
            let mut b = Block { o: [[0.0; LANES]; 3], d: [[0.0; LANES]; 3], tmax: [0.0; LANES] };
            for (l, r) in c.iter().enumerate() {
                for a in 0..3 {
                    b.o[a][l] = r.origin[a];
                    b.d[a][l] = r.dir[a];
                }
                b.tmax[l] = r.tmax;
            }
            b
        })
        .collect()
}

/// Seconds of one call of `f`.
fn seconds(f: impl FnOnce()) -> f64 {
    let t0 = Instant::now();
    f();
    t0.elapsed().as_secs_f64()
}

fn main() {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("scenes/cornell_box.ron");
    let mut app = App::with(prism::DefaultPlugins);
    app.resources.source = SceneSource::File(path);
    app.setup().expect("load scenes/cornell_box.ron");
    let scene = app.resources.scene.as_ref().expect("a loaded scene");
    let prims = &scene.prims;
    let tris: Vec<Tri> = prims
        .tris
        .iter()
        .map(|[a, b, c]| Tri { v0: (*a).into(), e1: (*b - *a).into(), e2: (*c - *a).into() })
        .collect();
    let plus: Vec<Plu> = prims.tris.iter().map(|[a, b, c]| plu((*a).into(), (*b).into(), (*c).into())).collect();
    let block_set = robust_block::PlueckerSet::new(&prims.tris).expect("the Cornell box's 36 triangles");
    let camera = camera_rays(scene, 256, 256);
    let (bounce, _) = secondary_rays(scene, &camera, 1);
    println!("wide kernel vs Prism's BVH, {} triangles, one thread, best of 15 interleaved rounds", tris.len());
    println!(
        "| rays | Prism BVH Mrays/s | 16 lanes dispatched | AVX2 | baseline SSE2 | dispatched / BVH | differing rays | Pluecker 16 lanes | Pluecker / BVH | Pluecker differing | block query | block / BVH | block differing |"
    );
    println!("|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|");
    // The bounce rays as the renderer spawns them, naming the triangle they leave (`Ray::leaves`), for the block
    // query, which leaves a ray that may re-hit its origin's surface to the one-ray query.
    let starts: Vec<u32> = camera.iter().filter_map(|r| scene.intersect(r)).map(|h| h.prim).collect();
    let bounce_leaving: Vec<Ray> = bounce.iter().zip(&starts).map(|(r, &p)| r.leaving(p)).collect();
    for (name, rays, block_rays) in [("camera", &camera, &camera), ("bounce", &bounce, &bounce_leaving)] {
        let blocks = blocks(rays);
        let n = blocks.len() * LANES;
        let rays = &rays[..n];
        let mut out = vec![0u32; n];
        let prism_hits: Vec<u32> =
            rays.iter().map(|r| scene.accel.intersect(prims, r).map_or(u32::MAX, |h| h.prim)).collect();
        let mut out_p = vec![0u32; n];
        let mut out_b = vec![None; n];
        let mut times = [f64::INFINITY; 6];
        for _ in 0..15 {
            times[0] = times[0].min(seconds(|| {
                for r in rays {
                    black_box(scene.accel.intersect(prims, black_box(r)));
                }
            }));
            times[1] = times[1].min(seconds(|| closest_dispatched(&tris, black_box(&blocks), &mut out)));
            times[2] = times[2].min(seconds(|| closest_avx2(&tris, black_box(&blocks), &mut out)));
            times[3] = times[3].min(seconds(|| closest_baseline(&tris, black_box(&blocks), &mut out)));
            times[4] = times[4].min(seconds(|| pluecker_dispatched(&plus, black_box(&blocks), &mut out_p)));
            times[5] = times[5].min(seconds(|| {
                robust_block::intersect_block(&block_set, scene, black_box(&block_rays[..n]), &mut out_b)
            }));
        }
        closest_dispatched(&tris, &blocks, &mut out);
        let differ = out.iter().zip(&prism_hits).filter(|(a, b)| a != b).count();
        pluecker_dispatched(&plus, &blocks, &mut out_p);
        let differ_p = out_p.iter().zip(&prism_hits).filter(|(a, b)| a != b).count();
        // The block query against the tree on the same rays (naming the triangle they leave): other primitives, and
        // of those, hits at another distance (more than 1e-5 relative; the rest are ties, such as a ray through the
        // edge two triangles share).
        let tree_b: Vec<_> = block_rays[..n].iter().map(|r| scene.accel.intersect(prims, r)).collect();
        let other: Vec<_> = out_b.iter().zip(&tree_b).filter(|(a, b)| a.map(|h| h.prim) != b.map(|h| h.prim)).collect();
        let far = other
            .iter()
            .filter(|(a, b)| match (a, b) {
                (Some(a), Some(b)) => (a.t - b.t).abs() > 1e-5 * b.t.abs().max(1.0),
                _ => true,
            })
            .count();
        let differ_b = format!("{} ({far} at another distance)", other.len());
        let unsure: usize = block_rays[..n]
            .chunks(robust_block::BLOCK)
            .map(|c| block_set.closest(c).unsure[..c.len()].iter().filter(|&&u| u).count())
            .sum();
        let differ_b = format!("{differ_b}; {:.2}% to the tree", 100.0 * unsure as f64 / n as f64);
        let m = times.map(|t| n as f64 / t / 1e6);
        println!(
            "| {name} ({n}) | {:.1} | {:.1} | {:.1} | {:.1} | {:.2} | {differ} | {:.1} | {:.2} | {differ_p} | {:.1} | {:.2} | {differ_b} |",
            m[0],
            m[1],
            m[2],
            m[3],
            m[1] / m[0],
            m[4],
            m[4] / m[0],
            m[5],
            m[5] / m[0]
        );
    }
}
