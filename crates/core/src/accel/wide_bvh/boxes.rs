//! One ray against the eight child boxes of a node: the slab test of the wide BVH, in two widths.
//!
//! [`RayBoxes`] tests the eight boxes as two groups of four with SSE (glam's `Vec4`), which every x86-64 CPU has;
//! [`RayBoxes8`] tests all eight with one AVX operation per step, through `pulp`'s safe wrappers of the AVX
//! intrinsics under a [`V3`] token (proof that the CPU has AVX2 and FMA, detected at run time; the traversal then
//! runs compiled for those features, see `WithSimd` in `mod.rs`). Both compute every lane with the same operations
//! in the same order, so their entry distances and masks are bit for bit the same and the traversal visits the same
//! nodes in the same order either way: the images do not depend on the CPU.
//!
//! The test is robust to axis-parallel rays (reciprocals clamped to +-1e25, -0 treated as +0) and conservative
//! against rounding (the exit distance scaled by `1 + 2 gamma(3)`, Ize 2013); empty slots hold a box from +inf to
//! -inf, which no ray meets.
//!
//! The same two types carry the traversal's other steps that have a faster form under AVX, each with the same
//! result as the baseline's: the stack slots of a node's hit children (compares instead of an insertion's branches)
//! and a leaf packet's lane (a permute instead of a jump on the lane number).

use super::{Node, WIDTH};
use crate::geometry::{Ray, TriPacket, TriSoa, gamma};
use core::arch::x86_64::{__m128, __m256, _CMP_EQ_OQ, _CMP_GT_OQ, _CMP_LE_OS};
use glam::{Vec3A, Vec4};
use pulp::x86::V3;

/// One ray's SIMD steps of the traversal: above all the box test, and the steps with a faster form under AVX.
pub(super) trait BoxTest {
    /// Entry distances of a node's children and the mask of those the ray meets within `(0, tmax)`.
    fn test(&self, n: &Node, tmax: f32) -> ([f32; WIDTH], u32);

    /// Triangle `lane` of a leaf packet in the form the exact kernel takes (glam's lane reads, which compile to
    /// a jump on the lane number).
    #[inline(always)]
    fn packet_lane(&self, p: &TriPacket, lane: usize) -> TriSoa {
        p.lane(lane)
    }

    /// Where each child goes among the hit children pushed on the stack, counted from the bottom: child `i`
    /// (bit `i` of `mask`) has below it every hit child farther than it and every hit child as far and of lower
    /// index (the order an insertion of the children in lane order, far to near, leaves), so the nearest is on
    /// top. Children not hit get the slots above the hit ones (written, but above the stack pointer).
    #[inline(always)]
    fn stack_slots(&self, t: &[f32; WIDTH], mask: u32) -> [u32; WIDTH] {
        let count = mask.count_ones();
        core::array::from_fn(|i| {
            let below = (1u32 << i) - 1;
            if mask & (1 << i) == 0 {
                return count + (!mask & below).count_ones();
            }
            let mut farther = 0u32;
            for (j, &tj) in t.iter().enumerate() {
                farther |= ((tj > t[i]) as u32 | ((tj == t[i]) as u32 & (j < i) as u32)) << j;
            }
            (farther & mask).count_ones()
        })
    }
}

/// A row of [`Node::b`]: which box plane. An enum rather than an index, so the compiler knows every value is
/// below 6 and indexes a node's planes without a bounds check (two instructions fewer per plane, twelve per node).
#[derive(Clone, Copy, Debug)]
#[repr(u8)]
enum Plane {
    MinX = 0,
    MinY = 1,
    MinZ = 2,
    MaxX = 3,
    MaxY = 4,
    MaxZ = 5,
}

/// The largest reciprocal direction component [`clamped_recip`] gives (its sign the component's).
pub(super) const RECIP_CLAMP: f32 = 1e25;

/// The box test's reciprocal of direction `dir`: components beyond +-[`RECIP_CLAMP`] clamped to it with the
/// direction's sign, -0 treated as +0 (the one-ray test uses it; the packet test computes the same lane by lane).
#[inline(always)]
pub(super) fn clamped_recip(dir: Vec3A) -> Vec3A {
    let d = dir + Vec3A::ZERO; // -0 becomes +0
    let r = d.recip();
    Vec3A::select(r.abs().cmpgt(Vec3A::splat(RECIP_CLAMP)), Vec3A::splat(RECIP_CLAMP).copysign(d), r)
}

/// The reciprocal direction with tiny components clamped, and per axis whether the near plane is the box's max
/// (a negative direction): `(inv, near planes, far planes)`.
#[inline(always)]
fn slabs(ray: &Ray) -> (Vec3A, [Plane; 3], [Plane; 3]) {
    let d = ray.dir + Vec3A::ZERO; // -0 becomes +0
    let inv = clamped_recip(ray.dir);
    let pick = |neg: bool, min: Plane, max: Plane| if neg { (max, min) } else { (min, max) };
    let (nx, fx) = pick(d.x < 0.0, Plane::MinX, Plane::MaxX);
    let (ny, fy) = pick(d.y < 0.0, Plane::MinY, Plane::MaxY);
    let (nz, fz) = pick(d.z < 0.0, Plane::MinZ, Plane::MaxZ);
    (inv, [nx, ny, nz], [fx, fy, fz])
}

/// The ray data of a traversal with SSE: origin and clamped reciprocal direction splatted, near and far planes.
pub(super) struct RayBoxes {
    o: [Vec4; 3],
    inv: [Vec4; 3],
    near: [Plane; 3],
    far: [Plane; 3],
}

impl RayBoxes {
    #[inline(always)]
    pub(super) fn new(ray: &Ray) -> Self {
        let (inv, near, far) = slabs(ray);
        RayBoxes {
            o: [Vec4::splat(ray.origin.x), Vec4::splat(ray.origin.y), Vec4::splat(ray.origin.z)],
            inv: [Vec4::splat(inv.x), Vec4::splat(inv.y), Vec4::splat(inv.z)],
            near,
            far,
        }
    }

    /// Children `4 g .. 4 g + 4`.
    #[inline(always)]
    fn test4(&self, n: &Node, g: usize, tmax: f32) -> (Vec4, u32) {
        let plane = |p: Plane| Vec4::from_slice(&n.b[p as usize][4 * g..4 * g + 4]);
        let t0 = (plane(self.near[0]) - self.o[0]) * self.inv[0];
        let t1 = (plane(self.near[1]) - self.o[1]) * self.inv[1];
        let t2 = (plane(self.near[2]) - self.o[2]) * self.inv[2];
        let u0 = (plane(self.far[0]) - self.o[0]) * self.inv[0];
        let u1 = (plane(self.far[1]) - self.o[1]) * self.inv[1];
        let u2 = (plane(self.far[2]) - self.o[2]) * self.inv[2];
        let tnear = t0.max(t1).max(t2.max(Vec4::ZERO));
        let tfar = u0.min(u1).min(u2.min(Vec4::splat(tmax))) * (1.0 + 2.0 * gamma(3));
        (tnear, tnear.cmple(tfar).bitmask())
    }
}

impl BoxTest for RayBoxes {
    #[inline(always)]
    fn test(&self, n: &Node, tmax: f32) -> ([f32; WIDTH], u32) {
        let (t_lo, m_lo) = self.test4(n, 0, tmax);
        let (t_hi, m_hi) = self.test4(n, 1, tmax);
        let mut t = [0f32; WIDTH];
        t[..4].copy_from_slice(&t_lo.to_array());
        t[4..].copy_from_slice(&t_hi.to_array());
        (t, m_lo | m_hi << 4)
    }
}

/// The ray data of a traversal with AVX: the same as [`RayBoxes`], eight lanes wide.
pub(super) struct RayBoxes8 {
    simd: V3,
    o: [__m256; 3],
    inv: [__m256; 3],
    near: [Plane; 3],
    far: [Plane; 3],
}

impl RayBoxes8 {
    #[inline(always)]
    pub(super) fn new(simd: V3, ray: &Ray) -> Self {
        let (inv, near, far) = slabs(ray);
        let a = simd.avx;
        RayBoxes8 {
            simd,
            o: [a._mm256_set1_ps(ray.origin.x), a._mm256_set1_ps(ray.origin.y), a._mm256_set1_ps(ray.origin.z)],
            inv: [a._mm256_set1_ps(inv.x), a._mm256_set1_ps(inv.y), a._mm256_set1_ps(inv.z)],
            near,
            far,
        }
    }
}

impl BoxTest for RayBoxes8 {
    #[inline(always)]
    fn test(&self, n: &Node, tmax: f32) -> ([f32; WIDTH], u32) {
        let a = self.simd.avx;
        let plane = |p: Plane| -> __m256 { pulp::cast(n.b[p as usize]) };
        let t0 = a._mm256_mul_ps(a._mm256_sub_ps(plane(self.near[0]), self.o[0]), self.inv[0]);
        let t1 = a._mm256_mul_ps(a._mm256_sub_ps(plane(self.near[1]), self.o[1]), self.inv[1]);
        let t2 = a._mm256_mul_ps(a._mm256_sub_ps(plane(self.near[2]), self.o[2]), self.inv[2]);
        let u0 = a._mm256_mul_ps(a._mm256_sub_ps(plane(self.far[0]), self.o[0]), self.inv[0]);
        let u1 = a._mm256_mul_ps(a._mm256_sub_ps(plane(self.far[1]), self.o[1]), self.inv[1]);
        let u2 = a._mm256_mul_ps(a._mm256_sub_ps(plane(self.far[2]), self.o[2]), self.inv[2]);
        // The operations of `RayBoxes::test4` in its order (`max(a, b)` / `min(a, b)` as SSE's `maxps` / `minps`).
        let tnear = a._mm256_max_ps(a._mm256_max_ps(t0, t1), a._mm256_max_ps(t2, a._mm256_setzero_ps()));
        let tfar = a._mm256_mul_ps(
            a._mm256_min_ps(a._mm256_min_ps(u0, u1), a._mm256_min_ps(u2, a._mm256_set1_ps(tmax))),
            a._mm256_set1_ps(1.0 + 2.0 * gamma(3)),
        );
        let mask = a._mm256_movemask_ps(a._mm256_cmp_ps::<_CMP_LE_OS>(tnear, tfar)) as u32;
        (pulp::cast(tnear), mask)
    }

    /// The same values as the default, without the jump: each coordinate's lane broadcast by a variable permute,
    /// the three vertices' values blended into one vector (whose fourth lane, like `Vec3A::new`'s, repeats the third).
    #[inline(always)]
    fn packet_lane(&self, p: &TriPacket, lane: usize) -> TriSoa {
        let (a, blend) = (self.simd.avx, self.simd.sse4_1);
        let idx = self.simd.sse2._mm_set1_epi32(lane as i32);
        let gather = |c: usize| -> Vec3A {
            let at = |v: Vec4| -> __m128 { a._mm_permutevar_ps(v.into(), idx) };
            let xy = blend._mm_blend_ps::<0b0010>(at(p.v[0][c]), at(p.v[1][c]));
            Vec3A::from(blend._mm_blend_ps::<0b1100>(xy, at(p.v[2][c])))
        };
        TriSoa { xs: gather(0), ys: gather(1), zs: gather(2) }
    }

    /// The same slots as the default, without branches: per child one broadcast and two compares against all eight
    /// distances.
    #[inline(always)]
    fn stack_slots(&self, t: &[f32; WIDTH], mask: u32) -> [u32; WIDTH] {
        let a = self.simd.avx;
        let tv: __m256 = pulp::cast(*t);
        let count = mask.count_ones();
        let mut slots = [0u32; WIDTH];
        for (i, slot) in slots.iter_mut().enumerate() {
            let below = (1u32 << i) - 1;
            let ti = a._mm256_set1_ps(t[i]);
            let gt = a._mm256_movemask_ps(a._mm256_cmp_ps::<_CMP_GT_OQ>(tv, ti)) as u32;
            let eq = a._mm256_movemask_ps(a._mm256_cmp_ps::<_CMP_EQ_OQ>(tv, ti)) as u32;
            let hit_slot = ((gt | eq & below) & mask).count_ones();
            let miss_slot = count + (!mask & below).count_ones();
            *slot = if mask & (1 << i) != 0 { hit_slot } else { miss_slot };
        }
        slots
    }
}
